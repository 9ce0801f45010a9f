//! A tiny, strict flag parser: every bad value becomes one line
//! `error: --FLAG ...` naming what is allowed, and exit status 2.

use crate::geometry::Direction;
use polyturn_sync::Ratio;
use std::collections::BTreeMap;

/// A refused command line: the flag and what is wrong with it.
#[derive(Debug, Clone, PartialEq)]
pub struct CliError(pub String);

impl CliError {
    pub fn flag(flag: &str, msg: impl std::fmt::Display) -> CliError {
        CliError(format!("--{flag} {msg}"))
    }
}

pub type CliResult<T> = Result<T, CliError>;

/// Parsed `--name value` and `--switch` flags of one subcommand.
#[derive(Debug)]
pub struct Args {
    values: BTreeMap<String, String>,
    switches: Vec<String>,
}

impl Args {
    /// `valued` flags take one value, `switches` none; anything else is refused.
    pub fn parse(argv: &[String], valued: &[&str], switches: &[&str]) -> CliResult<Args> {
        let mut args = Args { values: BTreeMap::new(), switches: Vec::new() };
        let mut it = argv.iter();
        while let Some(a) = it.next() {
            let Some(name) = a.strip_prefix("--") else {
                return Err(CliError(format!("unexpected argument '{a}' (flags start with --)")));
            };
            let (name, inline) = match name.split_once('=') {
                Some((n, v)) => (n, Some(v.to_string())),
                None => (name, None),
            };
            if switches.contains(&name) {
                args.switches.push(name.to_string());
            } else if valued.contains(&name) {
                let v = inline.or_else(|| it.next().cloned());
                let v = v.ok_or_else(|| CliError::flag(name, "needs a value"))?;
                args.values.insert(name.to_string(), v);
            } else {
                let known: Vec<String> = valued.iter().chain(switches).map(|f| format!("--{f}")).collect();
                return Err(CliError(format!("--{name} is not a flag here (known: {})", known.join(" "))));
            }
        }
        Ok(args)
    }

    pub fn has(&self, switch: &str) -> bool {
        self.switches.iter().any(|s| s == switch)
    }
    pub fn raw(&self, flag: &str) -> Option<&str> {
        self.values.get(flag).map(String::as_str)
    }
    pub fn required(&self, flag: &str) -> CliResult<&str> {
        self.raw(flag).ok_or_else(|| CliError::flag(flag, "is required"))
    }

    /// A finite number in (lo, hi] (`lo_open`) or [lo, hi].
    pub fn number(&self, flag: &str, lo: f64, hi: f64, lo_open: bool, unit: &str) -> CliResult<Option<f64>> {
        let Some(text) = self.raw(flag) else { return Ok(None) };
        let bad = || {
            let op = if lo_open { ">" } else { ">=" };
            CliError::flag(flag, format!("must be a finite number {op} {lo} and <= {hi} {unit} (got '{text}')"))
        };
        let v: f64 = text.trim().parse().map_err(|_| bad())?;
        let ok = v.is_finite() && v <= hi && if lo_open { v > lo } else { v >= lo };
        ok.then_some(Some(v)).ok_or_else(bad)
    }

    pub fn length_mm(&self, flag: &str) -> CliResult<Option<f64>> {
        self.number(flag, 0.0, 10_000.0, true, "mm")
    }
    pub fn required_length_mm(&self, flag: &str) -> CliResult<f64> {
        self.required(flag)?;
        Ok(self.length_mm(flag)?.unwrap_or_default())
    }

    /// A whole number in lo..=hi.
    pub fn whole(&self, flag: &str, lo: u64, hi: u64) -> CliResult<Option<u64>> {
        let Some(text) = self.raw(flag) else { return Ok(None) };
        match text.trim().parse::<u64>() {
            Ok(v) if (lo..=hi).contains(&v) => Ok(Some(v)),
            _ => Err(CliError::flag(flag, format!("must be a whole number in {lo}..={hi} (got '{text}')"))),
        }
    }

    pub fn ratio(&self, flag: &str) -> CliResult<Ratio> {
        let text = self.required(flag)?;
        Ratio::parse(text).map_err(|e| CliError::flag(flag, format!("{} (got '{text}')", e.describe())))
    }

    pub fn direction(&self, flag: &str) -> CliResult<Direction> {
        match self.required(flag)? {
            "same" => Ok(Direction::Same),
            "opposite" => Ok(Direction::Opposite),
            other => Err(CliError::flag(flag, format!("must be 'same' or 'opposite' (got '{other}')"))),
        }
    }

    /// One of `choices`, or `default` when absent.
    pub fn choice<'a>(&'a self, flag: &str, choices: &[&'a str], default: &'a str) -> CliResult<&'a str> {
        match self.raw(flag) {
            None => Ok(default),
            Some(v) if choices.contains(&v) => Ok(v),
            Some(v) => Err(CliError::flag(flag, format!("must be one of {} (got '{v}')", choices.join(", ")))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn argv(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn bad_values_name_the_flag_and_the_range() {
        let a = Args::parse(&argv("--depth nan --edges 13 --ratio 1/0"), &["depth", "edges", "ratio"], &[]).unwrap();
        assert!(a.length_mm("depth").unwrap_err().0.starts_with("--depth must be a finite number > 0"));
        assert!(a.whole("edges", 1, 12).unwrap_err().0.contains("1..=12"));
        assert!(a.ratio("ratio").unwrap_err().0.contains("zero denominator"));
    }

    #[test]
    fn unknown_flags_and_missing_values_are_refused() {
        assert!(Args::parse(&argv("--bogus 1"), &["depth"], &[]).is_err());
        assert!(Args::parse(&argv("--depth"), &["depth"], &[]).unwrap_err().0.contains("needs a value"));
        let a = Args::parse(&argv("--depth=2 --json"), &["depth"], &["json"]).unwrap();
        assert_eq!(a.length_mm("depth").unwrap(), Some(2.0));
        assert!(a.has("json"));
    }
}
