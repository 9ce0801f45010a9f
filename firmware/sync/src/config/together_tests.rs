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
