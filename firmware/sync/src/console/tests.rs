use super::*;
use crate::derived::Timing;
use proptest::prelude::*;

fn ctl() -> Controller {
    Controller::new(Config::default(), Timing::FIRMWARE)
}

fn say(c: &mut Controller, line: &str) -> (std::string::String, Action) {
    let (r, a) = handle(line.as_bytes(), c);
    (std::string::String::from(r.as_str()), a)
}

#[test]
fn a_machinist_sets_the_ratio_and_direction() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "set max-rpm 600").0, "ok max-rpm=600");
    assert_eq!(say(&mut c, "set ratio 11/3").0, "ok ratio=11/3");
    assert_eq!(say(&mut c, "set dir opposite").0, "ok dir=opposite");
    assert_eq!(say(&mut c, "get ratio").0, "ok ratio=11/3");
    assert!(say(&mut c, "get").0.contains(" dir=opposite "));
    assert!(say(&mut c, "status").0.starts_with("ok state=idle fault=none"));
}

#[test]
fn errors_name_the_field_and_change_nothing() {
    let mut c = ctl();
    let before = *c.config();
    assert_eq!(say(&mut c, "set ratio 0").0, "error: ratio must be greater than 0");
    assert!(say(&mut c, "set edges 40").0.starts_with("error: edges 1..=12"));
    assert!(say(&mut c, "set ratio 100").0.contains("max-rate"));
    assert!(say(&mut c, "set").0.starts_with("error: usage"));
    assert!(say(&mut c, "launch").0.starts_with("error:"));
    assert_eq!(*c.config(), before);
}

#[test]
fn save_only_while_idle_and_engage_refuses_while_faulted() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "save"), ("ok saving".into(), Action::Save));
    assert_eq!(say(&mut c, "engage").0, "ok engaging");
    assert_eq!(say(&mut c, "save").1, Action::None);
    assert!(say(&mut c, "set ratio 1").0.starts_with("error: stop first"));
    assert_eq!(say(&mut c, "set phase 10").0, "ok phase=10.000");
    c.trip(crate::state::Fault::EStop);
    assert!(say(&mut c, "engage").0.starts_with("error: a fault is latched"));
    let s = say(&mut c, "status").0;
    assert!(s.contains("fault=estop") && s.contains("reason="), "{s}");
}

proptest! {
    #[test]
    fn any_bytes_get_one_answer_and_errors_change_nothing(line in proptest::collection::vec(any::<u8>(), 0..120)) {
        let mut c = ctl();
        let before = *c.config();
        let (r, _) = handle(&line, &mut c);
        prop_assert!(r.starts_with("ok") || r.starts_with("error: "));
        prop_assert!(!r.contains('\n'));
        if r.starts_with("error") { prop_assert_eq!(*c.config(), before); }
    }

    #[test]
    fn random_set_commands_never_leave_invalid_settings(name in "[a-z-]{1,10}", value in "[-0-9./a-z]{0,12}") {
        let mut c = ctl();
        let line = std::format!("set {name} {value}");
        let _ = handle(line.as_bytes(), &mut c);
        prop_assert_eq!(c.config().validate(), Ok(()));
    }
}

#[test]
fn a_set_prepared_outside_the_lock_installs_what_apply_would() {
    let (mut a, mut b) = (ctl(), ctl());
    let cmd = parse(b"set ratio 5/2");
    let pre = prepare(&cmd, *b.config(), b.config_generation(), b.timing());
    apply(cmd, &mut a);
    apply_prepared(cmd, pre, &mut b);
    assert_eq!(a.config(), b.config());
    assert_eq!(a.derived(), b.derived(), "the figures derived outside are the ones installed");
}

#[test]
fn a_set_prepared_from_stale_settings_changes_nothing() {
    let mut c = ctl();
    let cmd = parse(b"set phase 10");
    let pre = prepare(&cmd, *c.config(), c.config_generation(), c.timing());
    assert_eq!(say(&mut c, "set ratio 5/2").0, "ok ratio=5/2"); // another change lands in between
    let before = *c.config();
    let (reply, _) = render(&apply_prepared(cmd, pre, &mut c));
    assert!(reply.starts_with("error: the settings changed meanwhile"), "{reply}");
    assert_eq!(*c.config(), before);
}
