//! Missing flags as a sentence: `geometry needs --cutter-radius,
//! --stock-radius (or --stock-diameter) and --ratio`, in the order `--help`
//! lists them, each with its alternatives, where clap says `--a and --b is
//! required` and names only the first flag of a group.

use super::{escaped, name, strings};
use clap::error::{ContextKind, ContextValue};

pub fn sentence(e: &clap::Error) -> String {
    let mut missing: Vec<Vec<String>> = strings(e, ContextKind::InvalidArg).iter().map(|a| alternatives(a)).collect();
    let path = command_path(e);
    if let Some(cmd) = find(&path) {
        // stable: what clap cannot place stays in clap's order
        missing.sort_by_key(|alts| alts.first().map_or(usize::MAX, |a| position(&cmd, a)));
    }
    let items: Vec<String> = missing
        .iter()
        .map(|alts| match alts.split_first() {
            Some((one, [])) => one.clone(),
            Some((one, others)) => format!("{one} (or {})", others.join(" or ")),
            None => String::new(),
        })
        .collect();
    let who = if path.is_empty() { "polyturn".to_string() } else { path.join(" ") };
    format!("{} needs {}", escaped(&who), escaped(&and_list(&items)))
}

/// clap writes a group as `<--stock-radius <MM>|--stock-diameter <MM>>`:
/// its flags, split where a `|` starts the next (a value name such as
/// `<same|opposite>` has a `|` too).
fn alternatives(arg: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = arg.strip_prefix('<').filter(|r| r.starts_with('-')).unwrap_or(arg);
    while let Some(at) = rest.find("|-") {
        out.push(name(&rest[..at]));
        rest = &rest[at + 1..];
    }
    out.push(name(rest));
    out
}

/// `a`, `a and b`, `a, b and c`.
fn and_list(items: &[String]) -> String {
    match items.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// The subcommands, from clap's usage line: `Usage: polyturn device set
/// [OPTIONS] <NAME>` is `["device", "set"]`.
fn command_path(e: &clap::Error) -> Vec<String> {
    let usage = match e.get(ContextKind::Usage) {
        Some(ContextValue::StyledStr(s)) => s.to_string(),
        _ => return Vec::new(),
    };
    let words = usage.trim_start().trim_start_matches("Usage:").split_whitespace().skip(1);
    words.take_while(|w| !w.starts_with(['[', '<', '-'])).map(String::from).collect()
}

fn find(path: &[String]) -> Option<clap::Command> {
    path.iter().try_fold(crate::cli::command(), |c, name| c.find_subcommand(name).cloned())
}

/// Where `--help` lists the flag (or the positional's value name).
fn position(cmd: &clap::Command, flag: &str) -> usize {
    cmd.get_arguments()
        .position(|a| match a.get_long() {
            Some(long) => flag.strip_prefix("--") == Some(long),
            None => a.get_value_names().is_some_and(|v| v.iter().any(|n| n.as_str() == flag)),
        })
        .unwrap_or(usize::MAX)
}

#[cfg(test)]
mod tests {
    fn said(line: &str) -> String {
        crate::cli::dispatch(&line.split_whitespace().map(String::from).collect::<Vec<_>>()).unwrap_err().0
    }

    #[test]
    fn missing_flags_read_as_a_sentence_in_help_order_with_their_alternatives() {
        assert_eq!(
            said("geometry"),
            "geometry needs --cutter-radius, --stock-radius (or --stock-diameter), --depth (or --across-flats), --ratio, --edges and --direction"
        );
        assert_eq!(said("setups --sides 6 --stock-radius 10"), "setups needs --depth (or --across-flats)");
        assert_eq!(
            said("setups --sides 6"),
            "setups needs --stock-radius (or --stock-diameter) and --depth (or --across-flats)"
        );
        assert_eq!(
            said("simulate --stock-diameter 20 --depth 1 --ratio 2:1"),
            "simulate needs --cutter-radius, --edges, --direction, --rpm and --revolutions"
        );
    }

    #[test]
    fn a_nested_command_and_a_positional_are_named_as_typed() {
        assert_eq!(said("device set"), "device set needs NAME and VALUE");
        assert_eq!(said("image Cargo.toml --bin a.bin"), "image needs --hex");
    }

    #[test]
    fn a_value_name_with_a_bar_is_not_taken_for_alternatives() {
        assert_eq!(super::alternatives("--direction <same|opposite>"), ["--direction"]);
        assert_eq!(super::alternatives("<--depth <MM>|--across-flats <MM>>"), ["--depth", "--across-flats"]);
        assert_eq!(super::alternatives("<FILE>"), ["FILE"]);
        assert_eq!(super::and_list(&[]), "");
    }
}
