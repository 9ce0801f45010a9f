//! `compensate`'s refusals name the X limit that sets the top speed.

use super::{run, CompensateArgs};
use clap::Parser;

#[derive(Parser)]
struct Line {
    #[command(flatten)]
    a: CompensateArgs,
}

const HEX: &str = "--cutter-radius 50 --stock-diameter 20 --depth 1.5 --ratio 2 --edges 3 --direction same";

fn compensate(flags: &str) -> Result<String, String> {
    let a = Line::try_parse_from(format!("compensate {HEX} {flags}").split_whitespace()).map_err(|e| e.to_string())?.a;
    run(a).map_err(|e| e.0)
}

#[test]
fn past_both_x_limits_the_one_that_sets_the_rpm_bound_is_named() {
    // the speed alone allows 103.3 rpm, the acceleration 10.3
    let e = compensate("--x-max-speed 12 --x-max-accel 10 --rpm 6000").unwrap_err();
    assert!(e.starts_with("--x-max-accel cannot straighten these flats"), "{e}");
    assert!(e.contains("exceeds 10 mm/s^2: at most 10.3 rpm"), "{e}");
    assert!(compensate("--x-max-speed 12 --x-max-accel 10 --rpm 10.3").is_ok());
    // the other way round: the speed allows 9.9 rpm, the acceleration 103
    let e = compensate("--x-max-speed 0.4 --x-max-accel 1000 --rpm 6000").unwrap_err();
    assert!(e.starts_with("--x-max-speed cannot straighten these flats"), "{e}");
    assert!(e.contains("exceeds 0.4 mm/s: at most 9.9 rpm"), "{e}");
}
