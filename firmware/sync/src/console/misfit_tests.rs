//! A `set` that does not fit with the others says the bound of the setting
//! being set, with the others' values, and the bound is exact: the bound
//! itself is taken, one past it refused.

use crate::config::{Config, Misfit, Rule};
use crate::console::{handle, REPLY_LEN};
use crate::controller::Controller;
use crate::timing::Timing;

fn board(sets: &[&str]) -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    for line in sets {
        let r = say(&mut c, line);
        assert!(r.starts_with("ok "), "{line}: {r}");
    }
    c
}

fn say(c: &mut Controller, line: &str) -> std::string::String {
    handle(line.as_bytes(), c).0.as_str().into()
}

const STEP_RATE: &str =
    "(max-rpm x ratio x steps/60 must not exceed max-rate: the motor must keep up at the lathe's top speed)";
const PULSE_RATE: &str = "(max-rate x 2 x pulse must not exceed 1 s: a step is a pulse high and as long low)";
const START_RATE: &str = "(start-rate must not exceed max-rate)";
const COMMAND_RATE: &str = "(the drive must take a command at least once per cutter revolution: max-rpm x ratio / 60 must not exceed 50 Hz for esc50, 400 for esc400, 2000 for oneshot125, pwm-hz for pwm)";

/// `set name value` on a board set up by `sets` is refused with `reply`,
/// changing nothing; `set name bound` is taken; `set name past` is refused
/// with the same reply but for the value.
fn refused_at(sets: &[&str], name: &str, value: &str, reply: &str, bound: &str, past: &str) {
    let mut c = board(sets);
    let before = *c.config();
    assert_eq!(say(&mut c, &std::format!("set {name} {value}")), reply, "{sets:?} set {name} {value}");
    assert_eq!(*c.config(), before);
    assert_eq!(say(&mut c, &std::format!("set {name} {past}")), reply, "{sets:?} set {name} {past}");
    let mut c = board(sets);
    assert_eq!(say(&mut c, &std::format!("set {name} {bound}")), std::format!("ok {name}={bound}"));
}

#[test]
fn a_ratio_too_fast_for_the_motor_is_refused_with_the_largest_ratio_and_the_others() {
    // 60 x 200 000 / (1 500 x 3 200) = 5/2
    let reply =
        std::format!("error: ratio must be at most 5/2 with max-rpm 1500, steps 3200 and max-rate 200000 {STEP_RATE}");
    refused_at(&[], "ratio", "3", &reply, "5/2", "501/200");
}

/// The largest ratio `set ratio` takes at or below `n/d`, by brute force
/// over every pair of terms (written apart from the console's search).
fn largest_typed(n: u64, d: u64) -> (u64, u64) {
    let mut best = (0, 1);
    for q in 1..=1000u64 {
        for p in 1..=1000u64 {
            if p * d <= n * q && p * best.1 > best.0 * q {
                best = (p, q);
            }
        }
    }
    best
}

#[test]
fn a_ratio_bound_the_board_cannot_state_is_given_as_the_largest_ratio_it_takes() {
    // (settings, the rule's bound on the ratio as n/d)
    for (settings, n, d) in [
        // 60 x 200 000 / (1 500 x 3 201) = 8000/3201 = 2.49921...
        (&["set steps 3201"][..], 8000, 3201),
        // 60 x 200 000 / (997 x 3 000) = 4.0120...
        (&["set steps 3000", "set ratio 11/7", "set max-rpm 997"][..], 12_000_000, 2_991_000),
        // 60 x 200 000 / (1 001 x 4 000) = 2.9970...
        (&["set steps 4000", "set ratio 1", "set max-rpm 1001"][..], 12_000_000, 4_004_000),
        // 60 x 2 501 / (1 x 60 000) = 2501/1000: stated as it is
        (&["set ratio 1", "set max-rpm 1", "set steps 60000", "set max-rate 2501"][..], 150_060, 60_000),
    ] {
        let (p, q) = largest_typed(n, d);
        let bound = if q == 1 { std::format!("{p}") } else { std::format!("{p}/{q}") };
        let mut c = board(settings);
        let reply = say(&mut c, "set ratio 1000");
        assert!(reply.starts_with(&std::format!("error: ratio must be at most {bound} with ")), "{reply}");
        assert_eq!(say(&mut c, &std::format!("set ratio {bound}")), std::format!("ok ratio={bound}"), "{settings:?}");
    }
    // 60 x 200 000 / (1 500 x 1 600) = 5, a whole ratio
    let mut c = board(&["set steps 1600"]);
    assert!(say(&mut c, "set ratio 6").starts_with("error: ratio must be at most 5 with max-rpm 1500, steps 1600 and"));
    assert_eq!(say(&mut c, "set ratio 5"), "ok ratio=5");
}

/// A ratio bound whose terms are at the most `set ratio` takes, 1000, is
/// said as a ratio, and taken.
#[test]
fn a_ratio_bound_with_a_term_of_1000_is_a_ratio_the_board_takes() {
    // 60 x 1 000 / (7 x 60) = 1000/7
    let sets = ["set ratio 1", "set max-rpm 7", "set steps 60", "set max-rate 1000"];
    let reply =
        std::format!("error: ratio must be at most 1000/7 with max-rpm 7, steps 60 and max-rate 1000 {STEP_RATE}");
    refused_at(&sets, "ratio", "1000", &reply, "1000/7", "500/3");
    // 60 x 7 / (10 x 6 000) = 7/1000
    let sets = ["set ratio 1/1000", "set max-rpm 10", "set steps 6000", "set max-rate 7"];
    let reply =
        std::format!("error: ratio must be at most 7/1000 with max-rpm 10, steps 6000 and max-rate 7 {STEP_RATE}");
    refused_at(&sets, "ratio", "1/100", &reply, "7/1000", "1/142");
}

#[test]
fn a_max_rpm_steps_or_max_rate_that_breaks_the_motors_rule_names_its_bound() {
    // 60 x 200 000 / (2 x 3 200) = 1 875 rpm
    let reply =
        std::format!("error: max-rpm must be at most 1875 with ratio 2, steps 3200 and max-rate 200000 {STEP_RATE}");
    refused_at(&[], "max-rpm", "5000", &reply, "1875", "1876");
    // 60 x 200 000 / (1 500 x 2) = 4 000 steps
    let reply =
        std::format!("error: steps must be at most 4000 with max-rpm 1500, ratio 2 and max-rate 200000 {STEP_RATE}");
    refused_at(&[], "steps", "1000000", &reply, "4000", "4001");
    // 1 500 x 2 x 3 200 / 60 = 160 000 steps/s; 7/3: 1 500 x 7 x 3 200 / 180 = 186 666.7, rounded up
    let reply =
        std::format!("error: max-rate must be at least 160000 with max-rpm 1500, ratio 2 and steps 3200 {STEP_RATE}");
    refused_at(&[], "max-rate", "1000", &reply, "160000", "159999");
    let reply =
        std::format!("error: max-rate must be at least 186667 with max-rpm 1500, ratio 7/3 and steps 3200 {STEP_RATE}");
    refused_at(&["set ratio 7/3"], "max-rate", "1000", &reply, "186667", "186666");
}

#[test]
fn a_pulse_or_max_rate_too_long_for_a_step_names_its_bound() {
    // 1 s / (2 x 200 000) = 2 500 ns
    let reply = std::format!("error: pulse must be at most 2500 with max-rate 200000 {PULSE_RATE}");
    refused_at(&[], "pulse", "3000", &reply, "2500", "2501");
    // 1 s / (2 x 3 000 ns) = 166 666.7 steps/s, rounded down
    let sets = ["set max-rpm 500", "set max-rate 100000", "set pulse 3000"];
    let reply = std::format!("error: max-rate must be at most 166666 with pulse 3000 {PULSE_RATE}");
    refused_at(&sets, "max-rate", "250000", &reply, "166666", "166667");
}

#[test]
fn a_start_rate_past_max_rate_names_max_rate() {
    let reply = std::format!("error: start-rate must be at most 200000 with max-rate 200000 {START_RATE}");
    refused_at(&[], "start-rate", "250000", &reply, "200000", "200001");
}

/// Lowering max-rate can break two rules: the floor named is the higher,
/// the one that fits both.
#[test]
fn a_max_rate_under_two_floors_names_the_higher() {
    let reply = std::format!("error: max-rate must be at least 170000 with start-rate 170000 {START_RATE}");
    refused_at(&["set start-rate 170000"], "max-rate", "1000", &reply, "170000", "169999");
    let reply =
        std::format!("error: max-rate must be at least 160000 with max-rpm 1500, ratio 2 and steps 3200 {STEP_RATE}");
    refused_at(&["set start-rate 150000"], "max-rate", "1000", &reply, "160000", "159999");
    // the same floor from both: the first rule broken is named
    refused_at(&["set start-rate 160000"], "max-rate", "1000", &reply, "160000", "159999");
}

/// A BLDC through an RC ESC at 50 Hz: raising the ratio or max-rpm breaks
/// the motor's rule and the drive's; the lower ceiling is named.
#[test]
fn a_bldc_drive_too_slow_for_the_cutter_names_the_lower_ceiling() {
    let bldc = ["set drive bldc"];
    // 60 x 50 / 1 500 = 2 (the motor's rule: 5/2)
    let reply = std::format!("error: ratio must be at most 2 with max-rpm 1500 and bldc-out esc50 {COMMAND_RATE}");
    refused_at(&bldc, "ratio", "3", &reply, "2", "501/250");
    // 60 x 50 / 2 = 1 500 (the motor's rule: 1 875)
    let reply = std::format!("error: max-rpm must be at most 1500 with ratio 2 and bldc-out esc50 {COMMAND_RATE}");
    refused_at(&bldc, "max-rpm", "2000", &reply, "1500", "1501");
    // with 100 counts a turn the motor's rule is far: 60 x 50 / 1 200 = 5/2
    let sets = ["set steps 100", "set max-rpm 1200", "set ratio 5/2", "set drive bldc"];
    let reply = std::format!("error: ratio must be at most 5/2 with max-rpm 1200 and bldc-out esc50 {COMMAND_RATE}");
    refused_at(&sets, "ratio", "3", &reply, "5/2", "501/200");
}

#[test]
fn a_pwm_frequency_too_low_for_the_cutter_names_its_floor_with_pwm_hz_among_the_settings() {
    let sets =
        ["set steps 50", "set bldc-out pwm", "set pwm-hz 2000", "set drive bldc", "set max-rpm 10000", "set ratio 10"];
    let mut c = board(&sets);
    // 10 000 x 10 / 60 = 1 666.7 Hz, rounded up
    let reply = say(&mut c, "set pwm-hz 1000");
    assert!(
        reply.starts_with(
            "error: pwm-hz must be at least 1667 with max-rpm 10000, ratio 10 and bldc-out pwm (the drive"
        ),
        "{reply}"
    );
    // the same ceiling from both (100 steps: 60 x 200 000 / (10 000 x 100)
    // = 12): the first rule broken is named
    let mut c = board(&sets.map(|l| if l == "set steps 50" { "set steps 100" } else { l }));
    let reply = say(&mut c, "set ratio 13");
    assert!(
        reply.starts_with(
            "error: ratio must be at most 12 with max-rpm 10000, steps 100 and max-rate 200000 (max-rpm x"
        ),
        "{reply}"
    );
    let mut c = board(&sets);
    // 60 x 2 000 / 10 000 = 12 (the motor's rule: 24)
    let reply = say(&mut c, "set ratio 13");
    assert!(
        reply
            .starts_with("error: ratio must be at most 12 with max-rpm 10000, bldc-out pwm and pwm-hz 2000 (the drive"),
        "{reply}"
    );
}

/// `drive` and `bldc-out` are no number: the rule and the values it joins.
#[test]
fn a_drive_or_interface_that_does_not_fit_says_the_rule_and_its_values() {
    let mut c = board(&["set max-rpm 1600"]);
    let rule = &COMMAND_RATE[1..COMMAND_RATE.len() - 1];
    assert_eq!(
        say(&mut c, "set drive bldc"),
        std::format!(
            "error: drive does not fit with the others: {rule} (with max-rpm 1600, ratio 2 and bldc-out esc50)"
        )
    );
    let mut c = board(&["set max-rpm 1600", "set bldc-out esc400", "set drive bldc"]);
    assert_eq!(
        say(&mut c, "set bldc-out esc50"),
        std::format!(
            "error: bldc-out does not fit with the others: {rule} (with max-rpm 1600, ratio 2 and bldc-out esc50)"
        )
    );
}

/// Every refusal of the kind, for every setting and rule, at the longest
/// values the settings take, fits a reply line whole (`REPLY_LEN`, with
/// room to spare).
#[test]
fn the_longest_refusal_fits_a_reply_line() {
    let config = Config {
        max_lathe_rpm: 10_000,
        ratio: crate::Ratio::new(999, 997).unwrap(),
        motor_steps_per_rev: 999_999,
        max_step_rate_hz: 249_999,
        step_pulse_ns: 9_999,
        start_rate_hz: 249_999,
        bldc_out: crate::config::BldcOut::OneShot125,
        drive: crate::DriveKind::Bldc,
        ..Config::default()
    };
    let mut longest = 0;
    for bldc_out in [crate::config::BldcOut::OneShot125, crate::config::BldcOut::Pwm] {
        for rule in Rule::ALL {
            for setting in crate::config::NAMES {
                let m = Misfit { setting, rule, config: Config { bldc_out, pwm_hz: 20_000, ..config } };
                let mut out = crate::console::Reply::new();
                super::write(&m, &mut out);
                assert!(out.starts_with("error: ") && out.ends_with(')'), "{out}");
                longest = longest.max(out.len());
            }
        }
    }
    assert!(longest < REPLY_LEN - 150, "{longest} of {REPLY_LEN}");
}

/// The search itself: the largest ratio in lowest terms, and none below
/// 1/1000, where the bound is said as a decimal (the console's bounds are
/// never that low: the others fit with a ratio of 1/1000 at least).
#[test]
fn the_largest_ratio_is_in_lowest_terms_and_a_bound_below_any_is_a_decimal() {
    assert_eq!(super::largest_at_most(5, 2), Some((5, 2)));
    assert_eq!(super::largest_at_most(12_000_000, 4_004_000), Some(largest_typed(12_000_000, 4_004_000)));
    assert_eq!(super::largest_at_most(1, 1000), Some((1, 1000)));
    assert_eq!(super::largest_at_most(1, 2000), None);
    for (n, d, text) in [(1, 2000, "0.0005"), (1, 3000, "0.0003..."), (5, 2, "5/2"), (4000, 1000, "4")] {
        let mut out = super::Reply::new();
        super::write_ratio(n, d, &mut out).unwrap();
        assert_eq!(out.as_str(), text, "{n}/{d}");
    }
}
