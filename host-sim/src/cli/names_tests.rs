//! One name per idea across the commands: `--direction` (the
//! console's `dir`), `--encoder-cpr` (the console's `cpr`), pulse widths
//! in ns (the console's `pulse` and `dir-setup`), and ratios as the shop
//! writes them. The old spellings are hidden aliases that still work.

use super::guided::{from_flags, GuidedArgs};
use super::{command, dispatch};
use clap::Parser;

fn run(line: &str) -> Result<String, String> {
    dispatch(&line.split_whitespace().map(String::from).collect::<Vec<_>>()).map_err(|e| e.0)
}

/// Every command's flags as `--help` shows them, with the command's path.
fn visible(c: &clap::Command, path: String, out: &mut Vec<(String, String)>) {
    for a in c.get_arguments().filter(|a| !a.is_hide_set()) {
        if let Some(long) = a.get_long() {
            out.push((path.clone(), format!("--{long}")));
        }
    }
    for s in c.get_subcommands() {
        visible(s, format!("{path} {}", s.get_name()), out);
    }
}

#[test]
fn each_idea_has_one_documented_flag_on_every_command() {
    let mut all = Vec::new();
    visible(&command(), "polyturn".into(), &mut all);
    for old in ["--sense", "--encoder-counts", "--pulse-us", "--dir-setup-us"] {
        assert!(all.iter().all(|(_, f)| f != old), "{old} is still documented");
    }
    for (cmd, flag) in [
        ("polyturn device setup", "--direction"),
        ("polyturn cam", "--encoder-cpr"),
        ("polyturn device setup", "--pulse-ns"),
    ] {
        assert!(all.iter().any(|(c, f)| c == cmd && f == flag), "{cmd} {flag}");
    }
}

#[test]
fn the_old_spellings_still_work_as_hidden_aliases() {
    let cam = "cam --sides 8 --inscribed-radius 20 --x-max-speed 12 --x-max-accel 2000 --rpm 12";
    assert_eq!(run(&format!("{cam} --encoder-counts 2000")), run(&format!("{cam} --encoder-cpr 2000")));
    assert!(run(&format!("{cam} --encoder-counts 4")).unwrap_err().starts_with("--encoder-cpr "));
    #[derive(Parser)]
    struct Line {
        #[command(flatten)]
        a: GuidedArgs,
    }
    let facts = |flags: &str| {
        let line = format!("setup --non-interactive --encoder-lines 600 --max-lathe-rpm 600 {flags}");
        let a = Line::try_parse_from(line.split_whitespace()).map_err(|e| e.to_string())?.a;
        from_flags(&a).map(|f| format!("{f:?}")).map_err(|e| e.0)
    };
    let new = facts("--direction opposite --pulse-ns 2500 --dir-setup-ns 5000").unwrap();
    assert_eq!(facts("--sense opposite --pulse-us 2.5 --dir-setup-us 5").unwrap(), new);
    assert!(new.contains("pulse_ns: Some(2500), dir_setup_ns: Some(5000), sense: Opposite"), "{new}");
    assert!(facts("--pulse-ns 2500 --pulse-us 2.5").unwrap_err().contains("cannot be used with"));
    assert!(facts("--pulse-ns 99").is_err() && facts("--pulse-ns 100").is_ok(), "the console's 100..=10000 ns");
    assert!(
        facts("--pulse-ns 10001").is_err() && facts("--pulse-ns 10000").is_ok() && facts("--dir-setup-ns 0").is_ok()
    );
}

#[test]
fn every_ratio_flag_takes_the_shops_notation() {
    let mut checked = 0;
    let mut all = vec![command()];
    while let Some(c) = all.pop() {
        for a in c.get_arguments().filter(|a| matches!(a.get_long(), Some("ratio" | "max-ratio" | "reduction"))) {
            for (typed, ok) in
                [("2", true), ("2/1", true), ("2:1", true), ("11:3", true), ("2:0", false), ("2:1:1", false)]
            {
                let alone = clap::Command::new("t").arg(a.clone());
                let parsed = alone.try_get_matches_from(["t", &format!("--{}", a.get_long().unwrap_or("")), typed]);
                assert_eq!(parsed.is_ok(), ok, "{} --{} {typed}", c.get_name(), a.get_long().unwrap_or(""));
            }
            checked += 1;
        }
        all.extend(c.get_subcommands().cloned());
    }
    assert_eq!(checked, 5, "geometry, simulate, compensate, setups --max-ratio and device setup --reduction");
    let colon =
        run("geometry --cutter-radius 50 --stock-radius 10 --depth 1 --ratio 11:3 --edges 1 --direction same --json");
    let slash =
        run("geometry --cutter-radius 50 --stock-radius 10 --depth 1 --ratio 11/3 --edges 1 --direction same --json");
    assert_eq!(colon, slash);
    assert!(colon.unwrap().contains("\"ratio\":\"11/3\""), "shown back in its canonical form");
}
