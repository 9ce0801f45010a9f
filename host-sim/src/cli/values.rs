//! The value parsers of every flag: each names what is allowed, with the
//! unit, so the one-line error (`error: --FLAG must be ... (got '...')`)
//! tells the machinist what to type. Surrounding spaces are trimmed for
//! every kind of value alike (numbers, ratios and choices). A range is
//! said as `lo..=hi`, and `--help` shows each flag's range as its parser
//! refuses it (`cli::ranges`): the two cannot disagree. A flag that is a
//! console setting takes the console's own range (`setting`). No number
//! takes a `+`, as the console's do not (`console::number`), whatever
//! Rust's own number parsers would take; a `-` is left to the range.

use crate::geometry::Direction;
use polyturn_sync::config::{BldcOut, Span};
use polyturn_sync::{DriveKind, Ratio};

/// A value parser as clap takes it: text in, value or what is allowed.
pub trait Parser<T>: Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {}
impl<T, F: Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static> Parser<T> for F {}

/// `s` trimmed, or `None` when it starts with `+` (which `str::parse`
/// takes and the console does not).
pub(crate) fn unplussed(s: &str) -> Option<&str> {
    Some(s.trim()).filter(|t| !t.starts_with('+'))
}

/// A finite number in [lo, hi] with its unit.
pub fn within(lo: f64, hi: f64, unit: &'static str) -> impl Parser<f64> {
    move |s: &str| match unplussed(s).map(str::parse::<f64>) {
        Some(Ok(v)) if v.is_finite() && (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!("must be a number in {lo}..={hi}{}", spaced(unit))),
    }
}

/// A length in mm, from a micron (finer is no lathe's, and a smaller one
/// would only come back in another flag's error as a 300-digit number) to
/// 10 m (a lathe, not a bridge).
pub fn length_mm() -> impl Parser<f64> {
    within(LENGTH_MM.0, LENGTH_MM.1, "mm")
}

/// The lengths a length flag takes, mm: a setup's own (`Setup::validate`).
pub use crate::geometry::LENGTH_MM;

/// A lathe speed: at least 1 rpm (slower is no cut), at most `hi`.
pub fn rpm(hi: f64) -> impl Parser<f64> {
    move |s: &str| match unplussed(s).map(str::parse::<f64>) {
        Some(Ok(v)) if v.is_finite() && (1.0..=hi).contains(&v) => Ok(v),
        _ => Err(format!("must be a lathe speed in 1..={hi} rpm")),
    }
}

/// A whole number in lo..=hi.
pub fn whole(lo: u64, hi: u64) -> impl Parser<u64> {
    move |s: &str| match unplussed(s).map(str::parse::<u64>) {
        Some(Ok(v)) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!("must be a whole number in {lo}..={hi}")),
    }
}

/// The same as `whole`, as u32.
pub fn whole32(lo: u32, hi: u32) -> impl Parser<u32> {
    let w = whole(lo.into(), hi.into());
    move |s: &str| w(s).map(|v| v as u32)
}

/// A console setting's number, in the console's own range (its table,
/// `polyturn_sync::config::table`), refused in its words.
pub fn setting(span: Span) -> impl Parser<u32> {
    move |s: &str| match unplussed(s).map(str::parse::<u32>) {
        Some(Ok(v)) if span.contains(v) => Ok(v),
        _ => Err(format!("must be {}", setting_range(span))),
    }
}

/// A console setting's range as the CLI says it: the console's words and
/// its name.
pub fn setting_range(span: Span) -> String {
    format!("{}, the console's `{}`", span.allowed, span.name)
}

/// A gear ratio as the console takes it (the core's own parser). A
/// decimal past the core's six places is told so, not called no decimal.
pub fn ratio(s: &str) -> Result<Ratio, String> {
    Ratio::parse(s).map_err(|e| match s.trim().split_once('.') {
        Some((_, frac)) if frac.len() > 6 && frac.bytes().all(|b| b.is_ascii_digit()) => {
            "must have at most 6 decimal places (or be written p/q, exactly)".to_string()
        }
        _ => e.describe().to_string(),
    })
}

/// A bound on the ratio in lo..=hi: a number (`7.5`) or a ratio as
/// `--ratio` takes it (`8:1`, `15/2`), read to its value and then held to
/// the one range whatever the spelling (`1/1000` is 0.001, as `0.001` is).
pub fn ratio_bound(lo: f64, hi: f64) -> impl Parser<f64> {
    move |s: &str| {
        let value = match s.contains(['/', ':']) {
            true => Ratio::parse(s).map(Ratio::to_f64).ok(),
            false => unplussed(s).and_then(|t| t.parse::<f64>().ok()),
        };
        value
            .filter(|v| v.is_finite() && (lo..=hi).contains(v))
            .ok_or_else(|| format!("must be {lo}..={hi}, as a number, p/q or p:q"))
    }
}

/// `same` or `opposite`: the cutter's sense against the lathe's.
pub fn direction(s: &str) -> Result<Direction, String> {
    match s.trim() {
        "same" => Ok(Direction::Same),
        "opposite" => Ok(Direction::Opposite),
        _ => Err("must be 'same' or 'opposite'".into()),
    }
}

/// `stepper` or `bldc`.
pub fn drive(s: &str) -> Result<DriveKind, String> {
    match s.trim() {
        "stepper" => Ok(DriveKind::Stepper),
        "bldc" => Ok(DriveKind::Bldc),
        _ => Err("must be 'stepper' or 'bldc'".into()),
    }
}

/// What a BLDC drive is fed: the console's `bldc-out` names.
pub fn bldc_out(s: &str) -> Result<BldcOut, String> {
    BldcOut::parse(s).map_err(|e| format!("must be {}", e.allowed))
}

/// A PWM frequency TIM10 makes exactly (the console's own rule, `pwm-hz`).
pub fn pwm_hz(s: &str) -> Result<u32, String> {
    let refused = || format!("must be {}", setting_range(polyturn_sync::config::table::PWM_HZ));
    let hz = unplussed(s).and_then(|t| t.parse::<u32>().ok()).ok_or_else(refused)?;
    polyturn_sync::config::bldc_out::check_pwm_hz(hz).map_err(|_| refused())?;
    Ok(hz)
}

/// A TCP port, 0..=65535 (0: any free port).
pub fn tcp_port(s: &str) -> Result<u16, String> {
    whole(0, 65_535)(s).map(|p| p as u16).map_err(|_| "must be a port number in 0..=65535 (0: any free port)".into())
}

/// An IPv4 or IPv6 address to listen on.
pub fn ip_address(s: &str) -> Result<std::net::IpAddr, String> {
    s.trim().parse().map_err(|_| "must be an IP address, such as 0.0.0.0 (every network) or 192.168.1.10".into())
}

/// A file to write: not empty.
pub fn out_file(s: &str) -> Result<std::path::PathBuf, String> {
    if s.trim().is_empty() {
        return Err("must be a file name".into());
    }
    Ok(s.into())
}

fn spaced(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parser_says_what_is_allowed_and_trims_alike() {
        assert_eq!(length_mm()(" 2.5 "), Ok(2.5));
        assert_eq!(direction(" same "), Ok(Direction::Same));
        assert_eq!(whole(1, 12)(" 12"), Ok(12));
        assert_eq!(length_mm()("nan").unwrap_err(), "must be a number in 0.001..=10000 mm");
        assert!(length_mm()("0").is_err() && length_mm()("10000.1").is_err() && length_mm()("inf").is_err());
        assert!(length_mm()("0.001").is_ok() && length_mm()("0.00099").is_err(), "a micron, not less");
        assert!(rpm(6000.0)("1e-308").unwrap_err().contains("1..=6000 rpm"));
        assert_eq!(whole(1, 12)("13").unwrap_err(), "must be a whole number in 1..=12");
        assert!(within(0.0, 0.5, "")("0").is_ok() && within(0.0, 0.5, "")("-0.1").is_err());
        assert_eq!(ratio("1/0").unwrap_err(), "has a zero denominator");
        assert!(drive("servo").is_err() && out_file(" ").is_err());
    }

    #[test]
    fn a_ratio_bound_is_a_number_or_a_ratio_as_the_shop_writes_it() {
        let b = ratio_bound(0.01, 1000.0);
        assert_eq!((b("7.5"), b("15/2"), b(" 15:2 "), b("1000:1")), (Ok(7.5), Ok(7.5), Ok(7.5), Ok(1000.0)));
        assert_eq!(b("0").unwrap_err(), "must be 0.01..=1000, as a number, p/q or p:q");
        assert!(b("0.01").is_ok() && b("1e-308").is_err());
        assert!(
            b("1001").is_err() && b("2:0").is_err() && b("nan").is_err() && ratio_bound(0.01, 8.0)("17:2").is_err()
        );
        assert_eq!(ratio(" 11:3 ").map(|r| r.to_string()), Ok("11/3".into()));
    }

    #[test]
    fn a_ratio_bound_is_one_check_for_every_spelling() {
        let b = ratio_bound(0.01, 1000.0);
        for (number, ratio) in [("0.001", "1/1000"), ("0.0099", "1/101"), ("1001", "1001/1")] {
            assert_eq!(b(ratio), b(number), "{ratio} as {number}");
            assert!(b(ratio).is_err(), "{ratio}");
        }
        assert_eq!((b("1/100"), b("0.01")), (Ok(0.01), Ok(0.01)));
    }

    #[test]
    fn a_setting_takes_the_consoles_range_and_says_it() {
        use polyturn_sync::config::table::{CPR, START_RATE};
        let cpr = setting(CPR);
        assert_eq!((cpr("4"), cpr(" 1000000")), (Ok(4), Ok(1_000_000)));
        assert_eq!(cpr("1048576").unwrap_err(), "must be 4..=1000000 counts per lathe rev, the console's `cpr`");
        assert!(cpr("3").is_err() && cpr("-4").is_err() && cpr("x").is_err());
        assert_eq!(setting(START_RATE)("0"), Ok(0));
    }

    #[test]
    fn no_number_takes_a_plus_as_the_ratio_and_the_console_do_not() {
        use polyturn_sync::config::table::CPR;
        let refused = [
            length_mm()("+2").is_err(),
            rpm(6000.0)("+600").is_err(),
            whole(1, 12)("+3").is_err(),
            setting(CPR)(" +2400").is_err(),
            ratio_bound(0.01, 1000.0)("+2").is_err(),
            pwm_hz("+1000").is_err(),
            ratio("+2").is_err(),
        ];
        assert_eq!(ratio("2.5000000").unwrap_err(), "must have at most 6 decimal places (or be written p/q, exactly)");
        assert_eq!(ratio("2.500000").map(|r| r.to_string()), Ok("5/2".into()));
        assert_eq!(refused, [true; 7]);
        assert_eq!((length_mm()("2"), whole(1, 12)("3")), (Ok(2.0), Ok(3)));
        assert_eq!(within(-0.45, 0.45, "counts")("-0.25"), Ok(-0.25), "a minus is left to the range");
    }
}
