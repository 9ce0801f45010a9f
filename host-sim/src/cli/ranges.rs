//! Each flag's range in its `--help`, in the words of its own parser's
//! refusal: the parser is asked for a value far out of any range, and the
//! `lo..=hi` part of what it refuses with is added to the flag's help.
//! So the help cannot say another range than the one a value is refused
//! by (a flag that is a console setting says the console's own, from its
//! table of settings).

/// A value no flag takes: every number parser refuses it naming its range.
const FAR: &str = "1e30";

/// `c` with each flag's range added to its help, at every depth.
pub fn in_help(c: clap::Command) -> clap::Command {
    c.mut_args(with_range).mut_subcommands(in_help)
}

fn with_range(a: clap::Arg) -> clap::Arg {
    let Some(range) = range_of(&a) else { return a };
    // before a `[default: ...]` written in the help, as clap puts its own after
    let add = |h: Option<&clap::builder::StyledStr>| {
        let h = h.map(|h| h.to_string()).unwrap_or_default();
        match h.find(" [default:") {
            _ if h.contains(&range) => h,
            Some(at) => format!("{} ({range}){}", &h[..at], &h[at..]),
            None => format!("{h} ({range})"),
        }
    };
    let (help, long) = (add(a.get_help()), a.get_long_help().map(|l| add(Some(l))));
    let a = a.help(help);
    match long {
        Some(l) => a.long_help(l),
        None => a,
    }
}

/// The range a flag's parser refuses `FAR` with: its words from the first
/// bound on (`must be a number in 0.01..=60 s` is `0.01..=60 s`). The
/// flag is parsed alone, freed of its ties to the others.
fn range_of(a: &clap::Arg) -> Option<String> {
    if !a.get_action().takes_values() {
        return None;
    }
    let none = || clap::builder::Resettable::<clap::Id>::Reset;
    let alone = a
        .clone()
        .required(false)
        .conflicts_with(none())
        .requires(none())
        .overrides_with(none())
        .group(none())
        .global(false);
    let argv = match a.get_long() {
        Some(long) => vec![format!("--{long}"), FAR.to_string()],
        None => vec![FAR.to_string()],
    };
    let probe = clap::Command::new("probe").no_binary_name(true).arg(alone);
    let e = probe.try_get_matches_from(argv).err().filter(|e| e.kind() == clap::error::ErrorKind::ValueValidation)?;
    let why = std::error::Error::source(&e)?.to_string();
    let at = why.find("..=")?;
    let start = why[..at].rfind(' ').map_or(0, |i| i + 1);
    Some(why[start..].to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flags_range_is_its_refusals() {
        let a = clap::Arg::new("t")
            .long("timeout")
            .help("How long")
            .value_parser(crate::cli::values::within(0.01, 60.0, "s"));
        assert_eq!(range_of(&a).as_deref(), Some("0.01..=60 s"));
        assert_eq!(with_range(a).get_help().map(|h| h.to_string()), Some("How long (0.01..=60 s)".into()));
        let words = clap::Arg::new("d").long("direction").value_parser(crate::cli::values::direction);
        assert_eq!(range_of(&words), None, "no range: the help is left as written");
    }
}
