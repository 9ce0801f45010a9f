//! `set` for every setting (`Config::with`): the field it changes, the
//! ends of its range (docs/src/console.md's settings table), and the two rules
//! that join settings (≤, so an exact fit passes), at their edges.

use super::*;

fn set(name: &str, value: &str) -> Result<Config, ConfigError> {
    Config::default().with(name, value)
}

#[test]
fn each_numeric_setting_lands_in_its_own_field() {
    let d = Config::default();
    assert_eq!(set("cpr", "4000"), Ok(Config { encoder_counts_per_rev: 4000, ..d }));
    assert_eq!(set("steps", "1600"), Ok(Config { motor_steps_per_rev: 1600, ..d }));
    assert_eq!(set("edges", "5"), Ok(Config { edges: 5, ..d }));
    assert_eq!(set("max-rate", "180000"), Ok(Config { max_step_rate_hz: 180_000, ..d }));
    assert_eq!(set("max-accel", "300000"), Ok(Config { max_accel_steps_per_s2: 300_000, ..d }));
    assert_eq!(set("ferror", "32"), Ok(Config { following_error_limit_steps: 32, ..d }));
    assert_eq!(set("phase", "-12.5"), Ok(Config { phase_offset_mdeg: -12_500, ..d }));
    assert_eq!(set("dir-setup", "2500"), Ok(Config { dir_setup_ns: 2_500, ..d }));
    assert_eq!(set("pulse", "1500"), Ok(Config { step_pulse_ns: 1_500, ..d }));
    assert_eq!(set("max-rpm", "900"), Ok(Config { max_lathe_rpm: 900, ..d }));
    assert_eq!(set("ratio", "5/2"), Ok(Config { ratio: Ratio::new(5, 2).unwrap(), ..d }));
}

#[test]
fn each_word_setting_takes_its_words_and_nothing_else() {
    let d = Config::default();
    assert_eq!(set("dir", "opposite"), Ok(Config { sense: Sense::Opposite, ..d }));
    assert_eq!(set("dir", " same "), Ok(d));
    assert_eq!(set("drive", "bldc"), Ok(Config { drive: DriveKind::Bldc, ..d }));
    assert_eq!(set("drive", "none"), Ok(Config { drive: DriveKind::None, ..d }));
    let bldc = Config { drive: DriveKind::Bldc, ..d };
    assert_eq!(bldc.with("drive", "stepper"), Ok(d));
    assert_eq!(set("enable", "high"), Ok(Config { enable_active_high: true, ..d }));
    let high = Config { enable_active_high: true, ..d };
    assert_eq!(high.with("enable", "low"), Ok(d));
    for (name, bad) in [("dir", "reverse"), ("drive", "servo"), ("enable", "on")] {
        assert_eq!(set(name, bad).unwrap_err().field, name, "{name} {bad}");
    }
}

#[test]
fn each_range_takes_its_ends_and_refuses_one_beyond() {
    // (a 1-step motor and a lathe at 1 rpm keep the joint limits out of it)
    let roomy = Config { max_lathe_rpm: 1, motor_steps_per_rev: 1, step_pulse_ns: 100, ..Config::default() };
    for (name, lo, hi, below, above) in [
        ("cpr", "4", "1000000", "3", "1000001"),
        ("steps", "1", "1000000", "0", "1000001"),
        ("edges", "1", "12", "0", "13"),
        ("max-rate", "1", "250000", "0", "250001"),
        ("max-accel", "10", "50000000", "9", "50000001"),
        ("ferror", "1", "1000000", "0", "1000001"),
        ("phase", "-360", "360", "-360.001", "360.001"),
        ("dir-setup", "0", "100000", "-1", "100001"),
        ("pulse", "100", "10000", "99", "10001"),
        ("max-rpm", "1", "10000", "0", "10001"),
    ] {
        let roomy = if name == "pulse" { Config { max_step_rate_hz: 1, ..roomy } } else { roomy };
        assert!(roomy.with(name, lo).is_ok(), "{name} {lo}");
        assert!(roomy.with(name, hi).is_ok(), "{name} {hi}");
        assert_eq!(roomy.with(name, below).unwrap_err().field, name, "{name} {below}");
        assert_eq!(roomy.with(name, above).unwrap_err().field, name, "{name} {above}");
    }
}

#[test]
fn a_step_period_of_twice_the_pulse_must_fit_the_top_rate() {
    // 200 000 steps/s × 2 × 2500 ns is exactly 1 s: allowed; 2501 ns is not
    assert!(set("pulse", "2500").is_ok());
    let e = set("pulse", "2501").unwrap_err();
    assert_eq!(e.field, "pulse");
    assert!(e.allowed.contains("max-rate x 2 x pulse"), "{}", e.allowed);
    // the same edge from the rate's side: 2000 ns allows 250 000 steps/s
    assert!(set("max-rate", "250000").is_ok());
    let longer = set("pulse", "2001").unwrap();
    assert_eq!(longer.with("max-rate", "250000").unwrap_err().field, "max-rate");
}

#[test]
fn the_motor_must_keep_up_at_the_lathes_top_speed_exactly() {
    // 1875 rpm × 2 × 3200 / 60 = 200 000 steps/s: exactly max-rate
    assert!(set("max-rpm", "1875").is_ok());
    let e = set("max-rpm", "1876").unwrap_err();
    assert_eq!(e.field, "max-rpm");
    assert!(e.allowed.contains("max-rpm x ratio x steps/60"), "{}", e.allowed);
    // the denominator counts: 1500 rpm × 8/3 × 3200 / 60 = 213 333 > 200 000
    assert!(set("ratio", "8/3").is_err());
    // 1500 × 5/2 × 3200 / 60 = 200 000: exactly
    assert!(set("ratio", "5/2").is_ok());
}

#[test]
fn the_motor_rate_at_a_lathe_speed_is_rpm_times_ratio_times_steps() {
    let c = set("ratio", "5/2").unwrap();
    // 300 rpm: 5 turns a second, 12.5 of the cutter, 40 000 steps
    assert_eq!(c.motor_rate_at(300.0), 40_000.0);
    assert_eq!(Config::default().motor_rate_at(60.0), 6_400.0);
}

#[test]
fn degrees_are_digits_with_an_optional_leading_minus_and_nothing_else() {
    for bad in ["+5", "+5.5", "5.+5", "-", ".", "-.", "--5", "0000001", "5.-5", "1e2", "000360", "05", "-05.5"] {
        assert_eq!(degrees_mdeg(bad, 360_000), None, "{bad}");
        assert_eq!(set("phase", bad).unwrap_err().field, "phase", "{bad}");
    }
    // the whole part as the documents write it, up to three decimals
    for bad in ["5.", ".25", "-.5", "5.1234", "5.1a", "5. "] {
        assert_eq!(degrees_mdeg(bad, 360_000), None, "{bad}");
    }
    assert_eq!(degrees_mdeg("360", 360_000), Some(360_000));
    assert_eq!(degrees_mdeg("-0.100", 360_000), Some(-100));
    assert_eq!(degrees_mdeg("-0", 360_000), Some(0));
    assert_eq!(degrees_mdeg("0.05", 360_000), Some(50), "a decimal's leading zero is a digit");
    assert_eq!(degrees_mdeg("12.5", 360_000), Some(12_500));
    assert_eq!(degrees_mdeg("12.345", 360_000), Some(12_345));
    assert_eq!(degrees_mdeg("2147484", i32::MAX), None, "whole degrees beyond i32 millidegrees");
    assert_eq!(degrees_mdeg("4294967296", i32::MAX), None, "beyond u32");
    assert_eq!(degrees_mdeg("2147483", i32::MAX), Some(2_147_483_000));
}

#[test]
fn a_whole_number_setting_takes_digits_without_sign_or_leading_zero() {
    let d = Config::default();
    for (name, bad) in [("cpr", "+5000"), ("cpr", "00004"), ("cpr", "04000"), ("steps", "+1600"), ("max-rpm", "0900")] {
        assert_eq!(set(name, bad).unwrap_err().field, name, "{name} {bad}");
    }
    assert_eq!(set("dir-setup", "0"), Ok(Config { dir_setup_ns: 0, ..d }), "0 itself is fine");
    assert_eq!(
        set("cpr", " 4000 "),
        Ok(Config { encoder_counts_per_rev: 4000, ..d }),
        "spaces around are not part of it"
    );
}

/// `start-rate` is 0 (off) to 250 000 Hz, and no faster than `max-rate`:
/// either way the refusal names the setting being set and changes nothing.
#[test]
fn the_start_rate_is_off_by_default_and_within_max_rate() {
    let d = Config::default();
    assert_eq!(d.start_rate_hz, 0);
    assert_eq!(set("start-rate", "1600"), Ok(Config { start_rate_hz: 1600, ..d }));
    assert_eq!(set("start-rate", "0"), Ok(d));
    let e = set("start-rate", "250001").unwrap_err();
    assert_eq!((e.field, e.allowed), ("start-rate", "0..=250000 Hz (0: off)"));
    let slow = d.with("max-rate", "180000").unwrap();
    let e = slow.with("start-rate", "180001").unwrap_err();
    assert_eq!(e.field, "start-rate");
    assert!(e.allowed.contains("must not exceed max-rate"), "{}", e.allowed);
    let started = d.with("start-rate", "5000").unwrap();
    assert_eq!(started.with("start-rate", "200001").unwrap_err().field, "start-rate");
    assert_eq!(started.with("start-rate", "200000").map(|c| c.start_rate_hz), Ok(200000));
}

/// A BLDC drive must take a command at least once per cutter turn at
/// `max-rpm`: max-rpm × num / den / 60 ≤ the frame rate. At 5/2 through
/// `esc50` that is 1 200 rpm; whichever setting crosses it is named.
#[test]
fn a_bldc_drive_slower_than_a_command_per_cutter_turn_is_refused() {
    // (a 100-count cutter encoder: the motor's own limit, max-rate, is
    // far away)
    let base = Config::default().with("steps", "100").unwrap().with("max-rpm", "1200").unwrap();
    let bldc = base.with("ratio", "5/2").unwrap().with("drive", "bldc").unwrap();
    assert_eq!(bldc.with("max-rpm", "1200").map(|c| c.max_lathe_rpm), Ok(1200));
    let e = bldc.with("max-rpm", "1201").unwrap_err();
    assert_eq!(e.field, "max-rpm");
    assert!(e.allowed.contains("once per cutter revolution"), "{}", e.allowed);
    // 400 Hz: 9 600 rpm at 5/2
    let fast = bldc.with("bldc-out", "esc400").unwrap();
    assert_eq!(fast.with("max-rpm", "9600").map(|c| c.max_lathe_rpm), Ok(9600));
    assert_eq!(fast.with("max-rpm", "9601").unwrap_err().field, "max-rpm");
    let fast = fast.with("max-rpm", "2000").unwrap();
    assert_eq!(fast.with("bldc-out", "esc50").unwrap_err().field, "bldc-out");
    // a stepper is not judged so
    let stepper = base.with("max-rpm", "1201").unwrap().with("ratio", "5/2").unwrap();
    assert_eq!(stepper.with("drive", "bldc").unwrap_err().field, "drive");
}

/// `bldc-tau` and `pwm-hz` out of range are refused naming themselves,
/// and change nothing.
#[test]
fn the_bldc_drives_time_constant_and_pwm_frequency_have_their_ranges() {
    let d = Config::default();
    assert_eq!(set("bldc-tau", "1").map(|c| c.bldc_tau_ms), Ok(1));
    assert_eq!(set("bldc-tau", "1000").map(|c| c.bldc_tau_ms), Ok(1000));
    for bad in ["0", "1001"] {
        let e = set("bldc-tau", bad).unwrap_err();
        assert_eq!((e.field, e.allowed), ("bldc-tau", crate::config::table::BLDC_TAU.allowed), "{bad}");
    }
    assert_eq!(set("pwm-hz", "7000").unwrap_err().field, "pwm-hz", "no whole number of 96 MHz counts");
    assert_eq!(set("pwm-hz", "8000").map(|c| c.pwm_hz), Ok(8000));
    assert_eq!(Config { bldc_tau_ms: 0, ..d }.validate().unwrap_err().field, "bldc-tau");
}
