use super::*;

#[test]
fn defaults_are_valid() {
    assert_eq!(Config::default().validate(), Ok(()));
}

#[test]
fn a_bad_value_names_the_field_and_changes_nothing() {
    let c = Config::default();
    for (name, value, field) in [
        ("ratio", "0", "ratio"),
        ("ratio", "1/0", "ratio"),
        ("edges", "13", "edges"),
        ("cpr", "-5", "cpr"),
        ("dir", "sideways", "dir"),
        ("phase", "400", "phase"),
        ("phase", "1.2345", "phase"),
        ("max-rate", "300000", "max-rate"),
        ("bogus", "1", "name"),
    ] {
        let e = c.with(name, value).unwrap_err();
        assert_eq!(e.field, field, "{name} {value}");
        assert!(!e.allowed.is_empty());
    }
    assert_eq!(c, Config::default());
}

#[test]
fn a_ratio_that_would_overspeed_the_motor_is_refused() {
    // 1500 rpm x 100 x 3200 / 60 = 16 MHz, far above 200 kHz.
    let e = Config::default().with("ratio", "100").unwrap_err();
    assert_eq!(e.field, "ratio");
    assert!(e.allowed.contains("max-rate"));
    // ...but fine once the machinist declares a slow lathe.
    let slow = Config::default().with("max-rpm", "30").unwrap();
    assert!(slow.with("ratio", "100").is_ok());
}

#[test]
fn phase_accepts_decimal_degrees() {
    let c = Config::default().with("phase", "-12.5").unwrap();
    assert_eq!(c.phase_offset_mdeg, -12_500);
    assert_eq!(Config::default().with("phase", "0.25").unwrap().phase_offset_mdeg, 250);
}

#[test]
fn a_limit_joining_settings_blames_the_one_being_set() {
    // 1500 rpm x 2 x 8000 / 60 = 400 kHz > 200 kHz: the steps did it.
    let e = Config::default().with("steps", "8000").unwrap_err();
    assert_eq!(e.field, "steps");
    assert!(e.allowed.contains("max-rate"), "{}", e.allowed);
    for (name, value) in [("max-rpm", "10000"), ("max-rate", "1000"), ("pulse", "10000")] {
        assert_eq!(Config::default().with(name, value).unwrap_err().field, name);
    }
    // ...while a field out of its own range still names itself
    assert_eq!(Config::default().with("steps", "0").unwrap_err().field, "steps");
    // and `validate` on a whole record names the check's own field
    let c = Config { motor_steps_per_rev: 8000, ..Config::default() };
    assert_eq!(c.validate().unwrap_err().field, "ratio");
}
