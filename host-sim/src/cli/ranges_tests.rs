//! Every flag's `--help` says the range its parser refuses by: the bounds
//! a refusal names are in the help, for every option of every command.

use super::errors::{adapt, CliError};

/// Every option taking a value, as (the command's path, its long name, its help).
fn options(c: &clap::Command, path: &[String], out: &mut Vec<(Vec<String>, String, String)>) {
    for a in c.get_arguments().filter(|a| a.get_action().takes_values()) {
        if let Some(long) = a.get_long() {
            let help = a.get_long_help().or(a.get_help()).map(|h| h.to_string()).unwrap_or_default();
            out.push((path.to_vec(), long.to_string(), help));
        }
    }
    for s in c.get_subcommands() {
        options(s, &[path, &[s.get_name().to_string()]].concat(), out);
    }
}

/// The numbers written in `text` (`0.01`, `-0.45`, `1000000`).
fn numbers(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    for c in text.chars().chain([' ']) {
        let part = c.is_ascii_digit() || (c == '.' && !cur.is_empty()) || (c == '-' && cur.is_empty());
        if part {
            cur.push(c);
            continue;
        }
        let n = cur.trim_end_matches('.').trim_start_matches('-');
        if n.chars().any(|c| c.is_ascii_digit()) {
            out.push(n.to_string());
        }
        cur.clear();
    }
    out
}

/// What the command line says of `--long VALUE` alone: the refusal of the
/// value, or None if the value itself was taken.
fn refusal(path: &[String], long: &str, value: &str) -> Option<String> {
    let argv: Vec<String> = path.iter().cloned().chain([format!("--{long}"), value.to_string()]).collect();
    let r = super::command().try_get_matches_from(std::iter::once("polyturn".to_string()).chain(argv));
    let valued = matches!(
        r.as_ref().err().map(|e| e.kind()),
        Some(clap::error::ErrorKind::ValueValidation | clap::error::ErrorKind::InvalidValue)
    );
    match adapt(r) {
        Err(CliError(e)) if valued => Some(e),
        _ => None,
    }
}

#[test]
fn every_bound_a_refusal_names_is_in_the_flags_help() {
    let mut all = Vec::new();
    options(&super::command(), &[], &mut all);
    let mut checked = 0;
    for (path, long, help) in &all {
        for probe in ["1e30", "-1e30", "0.0000001"] {
            let Some(said) = refusal(path, long, probe) else { continue };
            let why = said.split(" (got").next().unwrap_or(&said).to_string();
            // a bound, not the syntax's example (`a decimal like 2.5`)
            let bounded = ["..=", "<", ">", "greater", "less", "at most", "at least"].iter().any(|b| why.contains(b));
            for n in numbers(&why).into_iter().filter(|_| bounded) {
                assert!(
                    numbers(help).contains(&n),
                    "{} --{long}: the refusal of {probe} names {n}, the help does not:\n  refusal: {said}\n  help: {help}",
                    path.join(" ")
                );
            }
            checked += 1;
        }
        assert!(!help.contains("(> 0") && !help.contains("(<= "), "{} --{long}: {help}", path.join(" "));
    }
    assert!(checked > 100, "the walk refused values ({checked})");
}
