//! The refusals of `simulate` name the flag, its bound and what it got.

use super::super::{scenario_from, SimulateArgs};
use clap::Parser;

#[derive(Parser)]
struct Line {
    #[command(flatten)]
    a: SimulateArgs,
}

const HEX: &str = "--cutter-radius 50 --stock-diameter 20 --depth 1.5 --edges 3 --direction same --revolutions 3";

fn scenario(flags: &str) -> Result<(), String> {
    let line = format!("simulate {HEX} {flags}");
    let a = Line::try_parse_from(line.split_whitespace()).map_err(|e| e.to_string())?.a;
    scenario_from(&a).map(|_| ()).map_err(|e| e.0)
}

#[test]
fn an_rpm_too_fast_for_the_motor_is_refused_with_the_fastest_rpm_that_works() {
    // 200 000 steps/s over 2 x 3 200 steps a turn: 1 875 lathe rpm, of
    // which --rpm takes 10/13 (30 % headroom): 1 442
    let e = scenario("--ratio 2 --rpm 6000").unwrap_err();
    assert_eq!(
        e,
        "--rpm must be at most 1442 rpm for ratio 2 at 3200 steps a turn (the board's max-rate 200000 steps/s, with 30 % headroom) (got 6000)"
    );
    assert_eq!(scenario("--ratio 2 --rpm 1442"), Ok(()));
    assert!(scenario("--ratio 2 --rpm 1443").unwrap_err().starts_with("--rpm must be at most 1442 rpm "));
    assert!(scenario("--ratio 2 --rpm 1442.5").unwrap_err().ends_with("(got 1442.5)"));
}

#[test]
fn the_fastest_rpm_named_is_taken_and_one_more_is_refused() {
    for (ratio, steps) in [("2", 3200), ("5/2", 3200), ("8/3", 1600), ("3", 800), ("7/4", 51200), ("1/3", 100000)] {
        let flags = |rpm: u32| format!("--ratio {ratio} --motor-steps {steps} --rpm {rpm}");
        let e = scenario(&flags(6000)).unwrap_err();
        let bound: u32 =
            e.strip_prefix("--rpm must be at most ").and_then(|t| t.split(' ').next()).unwrap().parse().unwrap();
        assert_eq!(scenario(&flags(bound)), Ok(()), "{ratio} {steps}: {e}");
        let over = scenario(&flags(bound + 1)).unwrap_err();
        assert!(over.contains(&format!("at most {bound} rpm for ratio {ratio} at {steps} steps a turn")), "{over}");
        assert!(over.ends_with(&format!("(got {})", bound + 1)), "{over}");
    }
}

#[test]
fn a_motor_no_rpm_can_drive_is_refused_naming_its_steps() {
    // 1 000 000 steps x 1000: past 200 000 steps/s at the least max-rpm, 60
    let e = scenario("--ratio 1000 --motor-steps 1000000 --rpm 1").unwrap_err();
    assert!(e.starts_with("--rpm cannot be met at any speed: ratio 1000 at 1000000 steps a turn"), "{e}");
    assert!(e.ends_with("(lower --motor-steps) (got 1)"), "{e}");
}

#[test]
fn a_bldc_rpm_bound_named_by_the_first_refusal_is_taken_and_one_more_is_refused() {
    // the step rate allows 1 442 rpm at 2 x 3 200 counts; an RC ESC's
    // frame rate less (esc50: 50 x 60 / 2 = 1 500 board rpm, --rpm 1 153)
    for out in ["esc50", "esc400", "oneshot125", "pwm"] {
        let flags = |rpm: u32| format!("--ratio 2 --drive bldc --bldc-out {out} --rpm {rpm}");
        let e = scenario(&flags(6000)).unwrap_err();
        let bound: u32 = e
            .strip_prefix("--rpm must be at most ")
            .and_then(|t| t.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{out}: {e}"));
        assert!(e.ends_with("(got 6000)"), "{e}");
        assert_eq!(scenario(&flags(bound)), Ok(()), "{out}: {e}");
        let over = scenario(&flags(bound + 1)).unwrap_err();
        assert!(over.starts_with(&format!("--rpm must be at most {bound} rpm ")), "{out}: {over}");
        assert!(over.ends_with(&format!("(got {})", bound + 1)), "{over}");
    }
    let e = scenario("--ratio 2 --drive bldc --rpm 6000").unwrap_err();
    assert!(e.starts_with("--rpm must be at most 1153 rpm for ratio 2 with --bldc-out esc50 (50 commands/s"), "{e}");
}

#[test]
fn a_bldc_ratio_no_rpm_can_command_is_refused_naming_a_faster_drive() {
    // 60 board rpm x 60 / 60 = 60 commands/s, past esc50's 50
    let e = scenario("--ratio 60 --motor-steps 200 --drive bldc --bldc-tau 20 --rpm 10").unwrap_err();
    assert!(e.starts_with("--rpm cannot be met at any speed: ratio 60 with --bldc-out esc50"), "{e}");
    assert!(e.contains("oneshot125 or pwm"), "{e}");
}
