//! `try_with` keeps a misfit whole; `with` says it as the setting and the
//! rule's words, as the host's flags quote them.

use super::*;
use crate::config::table::MAX_RPM;

#[test]
fn a_set_that_does_not_fit_is_a_misfit_naming_the_setting_and_its_rule() {
    let d = Config::default();
    let Err(SetError::Together(m)) = d.try_with("steps", "8000") else { panic!("steps 8000 fits") };
    assert_eq!((m.setting, m.rule), ("steps", Rule::StepRate));
    assert_eq!(m.config, Config { motor_steps_per_rev: 8000, ..d }, "the settings it would have made");
    assert_eq!(m.bound(), Some(Bound { at_most: true, num: 60 * 200_000, den: 1500 * 2 }));
    let e = d.with("steps", "8000").unwrap_err();
    assert_eq!((e.field, e.allowed), ("steps", Rule::StepRate.error().allowed));
    assert_eq!(SetError::Together(m).error(), e);
    assert!(e.allowed.starts_with("does not fit with the others: max-rpm x ratio x steps/60"), "{}", e.allowed);
}

#[test]
fn a_value_wrong_alone_is_refused_alone() {
    let d = Config::default();
    assert_eq!(d.try_with("max-rpm", "0"), Err(SetError::Alone(MAX_RPM.error())));
    assert_eq!(d.with("max-rpm", "0"), Err(MAX_RPM.error()));
    assert_eq!(d.try_with("max-rpm", "900"), d.with("max-rpm", "900").map_err(SetError::Alone));
}

#[test]
fn each_rule_holds_at_its_edge_and_not_past_it() {
    let d = Config::default();
    for (rule, edge, past) in [
        (Rule::PulseRate, Config { step_pulse_ns: 2500, ..d }, Config { step_pulse_ns: 2501, ..d }),
        (Rule::StepRate, Config { max_lathe_rpm: 1875, ..d }, Config { max_lathe_rpm: 1876, ..d }),
        (Rule::StartRate, Config { start_rate_hz: 200_000, ..d }, Config { start_rate_hz: 200_001, ..d }),
        (
            Rule::CommandRate,
            Config { drive: DriveKind::Bldc, ..d },
            Config { drive: DriveKind::Bldc, max_lathe_rpm: 1501, ..d },
        ),
    ] {
        assert!(rule.holds(&edge), "{rule:?}");
        assert!(!rule.holds(&past), "{rule:?}");
        assert_eq!(past.validate(), Err(rule.error()), "{rule:?}");
        assert_eq!(Misfit::of("edges", &edge), None, "{rule:?}");
        assert_eq!(Misfit::of("edges", &past).map(|m| m.rule), Some(rule), "{rule:?}");
    }
    assert!(Rule::CommandRate.holds(&Config { max_lathe_rpm: 1501, ..d }), "a stepper is not judged so");
}

/// Every bound, worked by hand at a ratio of 7/3 (a denominator that is
/// not 1), with pwm-hz among the settings.
#[test]
fn each_rule_bounds_each_of_its_numbers_as_worked_by_hand() {
    let c = Config {
        ratio: crate::Ratio::new(7, 3).unwrap(),
        max_lathe_rpm: 900,
        motor_steps_per_rev: 1600,
        max_step_rate_hz: 150_000,
        step_pulse_ns: 2000,
        start_rate_hz: 5000,
        drive: DriveKind::Bldc,
        bldc_out: BldcOut::Pwm,
        pwm_hz: 4000,
        ..Config::default()
    };
    let most = |num, den| Some(Bound { at_most: true, num, den });
    let least = |num, den| Some(Bound { at_most: false, num, den });
    for (rule, setting, bound) in [
        (Rule::PulseRate, "max-rate", most(1_000_000_000, 4000)),
        (Rule::PulseRate, "pulse", most(1_000_000_000, 300_000)),
        (Rule::StepRate, "max-rpm", most(60 * 3 * 150_000, 7 * 1600)),
        (Rule::StepRate, "ratio", most(60 * 150_000, 900 * 1600)),
        (Rule::StepRate, "steps", most(60 * 3 * 150_000, 900 * 7)),
        (Rule::StepRate, "max-rate", least(900 * 7 * 1600, 60 * 3)),
        (Rule::StartRate, "start-rate", most(150_000, 1)),
        (Rule::StartRate, "max-rate", least(5000, 1)),
        (Rule::CommandRate, "max-rpm", most(60 * 3 * 4000, 7)),
        (Rule::CommandRate, "ratio", most(60 * 4000, 900)),
        (Rule::CommandRate, "pwm-hz", least(900 * 7, 60 * 3)),
        (Rule::CommandRate, "drive", None),
        (Rule::CommandRate, "bldc-out", None),
        (Rule::StepRate, "cpr", None),
    ] {
        assert_eq!(rule.bound(setting, &c), bound, "{rule:?} {setting}");
    }
    let esc = Config { bldc_out: BldcOut::Esc400, ..c };
    assert_eq!(Rule::CommandRate.bound("pwm-hz", &esc), None, "pwm-hz is no part of it without pwm");
    assert_eq!(Rule::CommandRate.bound("ratio", &esc), most(60 * 400, 900));
    assert_eq!(Rule::CommandRate.settings(&c), ["max-rpm", "ratio", "bldc-out", "pwm-hz"]);
    assert_eq!(Rule::CommandRate.settings(&esc), ["max-rpm", "ratio", "bldc-out"]);
}

/// The rules with a denominator, at their edges: 7/3 at 900 rpm and 1 600
/// steps needs 56 000 steps/s; 5/2 through 50 Hz, 1 200 rpm.
#[test]
fn the_rules_with_a_ratio_hold_at_their_edge_for_a_fractional_ratio() {
    let d = Config::default();
    let steps = Config { ratio: crate::Ratio::new(7, 3).unwrap(), max_lathe_rpm: 900, motor_steps_per_rev: 1600, ..d };
    assert!(Rule::StepRate.holds(&Config { max_step_rate_hz: 56_000, ..steps }));
    assert!(!Rule::StepRate.holds(&Config { max_step_rate_hz: 55_999, ..steps }));
    let bldc = Config { ratio: crate::Ratio::new(5, 2).unwrap(), drive: DriveKind::Bldc, ..d };
    assert!(Rule::CommandRate.holds(&Config { max_lathe_rpm: 1200, ..bldc }));
    assert!(!Rule::CommandRate.holds(&Config { max_lathe_rpm: 1201, ..bldc }));
}

/// Of two bounds on the same side, the tighter: the lower ceiling, the
/// higher floor; an equal one is not tighter.
#[test]
fn the_tighter_bound_is_the_lower_ceiling_or_the_higher_floor() {
    let b = |at_most, num, den| Bound { at_most, num, den };
    // 7/4 = 1.75 < 9/5 = 1.8
    assert!(b(true, 7, 4).tighter_than(&b(true, 9, 5)));
    assert!(!b(true, 9, 5).tighter_than(&b(true, 7, 4)));
    assert!(b(false, 9, 5).tighter_than(&b(false, 7, 4)));
    assert!(!b(false, 7, 4).tighter_than(&b(false, 9, 5)));
    for at_most in [true, false] {
        assert!(!b(at_most, 14, 8).tighter_than(&b(at_most, 7, 4)), "{at_most}: equal");
    }
}
