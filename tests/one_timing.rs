//! One timing: the tick rate and step-timer clock the host simulates, the
//! fake board and the page check settings with, and the sync core's tests
//! use, are the board's own (`polyturn_firmware::clocks`, built from the
//! PLL and bus dividers that `app::clocks` gives embassy). A second,
//! hand-written clock or tick rate anywhere in the sources fails here.

use polyturn_sync::Timing;
use std::path::Path;

#[test]
fn the_host_plans_with_the_clock_the_board_makes() {
    assert_eq!(polyturn_firmware::clocks::TIMING, Timing::FIRMWARE);
    assert_eq!(polyturn_bench::hwsim::TIMER_HZ, polyturn_firmware::clocks::CLOCKS.apb2_timer_hz());
    assert_eq!(polyturn_firmware::quadgen::TIMER_HZ, Timing::FIRMWARE.step_timer_hz);
}

/// Every `.rs` file under `dir`, skipping build output.
fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name();
        if name == "target" || name.to_string_lossy().starts_with('.') {
            continue;
        }
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_source_writes_a_clock_or_a_tick_of_its_own() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for d in ["firmware", "host-sim", "bench", "web", "fuzz", "tests"] {
        sources(&root.join(d), &mut files);
    }
    assert!(files.len() > 100, "the walk found the sources ({} files)", files.len());
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (n, line) in text.lines().enumerate() {
            let literal = |key: &str| {
                line.split(key).nth(1).is_some_and(|rest| rest.trim_start().starts_with(|c: char| c.is_ascii_digit()))
            };
            let hundred_mhz = line
                .match_indices("100_000_000")
                .any(|(i, _)| !line[..i].ends_with(|c: char| c.is_ascii_digit() || c == '_'));
            let own_clock = literal("step_timer_hz:") || literal("TIMER_HZ: u32 =") || hundred_mhz;
            let own_tick =
                literal("tick_hz:") || ["u32", "u64", "f64"].iter().any(|t| literal(&format!("TICK_HZ: {t} =")));
            // the one Timing, and the tree it is checked against (its
            // limits), which the board's TICK_HZ is taken from
            let the_one = (f.ends_with("sync/src/timing.rs") && line.contains("pub const FIRMWARE"))
                || f.ends_with("firmware/src/clocks.rs");
            if (own_clock || own_tick) && !the_one && !f.ends_with("one_timing.rs") {
                found.push(format!("{}:{}: {}", f.display(), n + 1, line.trim()));
            }
        }
    }
    assert!(found.is_empty(), "a clock or tick written by hand, not Timing::FIRMWARE:\n{}", found.join("\n"));
}
