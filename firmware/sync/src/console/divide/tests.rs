//! `divide` through the console: its refusals name the range and change
//! nothing; the readout in its reply and in `status`.

use crate::console::{handle, Action};
use crate::controller::Controller;
use crate::{Config, TickInput, Timing};

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

fn say(c: &mut Controller, line: &str) -> std::string::String {
    let (r, a) = handle(line.as_bytes(), c);
    assert_eq!(a, Action::None, "{line}");
    r.as_str().into()
}

const RANGE: &str = "error: divide 1..=3600 divisions of a turn, at most cpr/4 (4 counts or more apart)";

#[test]
fn a_number_out_of_range_or_no_number_is_refused_with_the_range_and_changes_nothing() {
    let mut c = ctl();
    for bad in [
        "divide 0",
        "divide 1e9",
        "divide 1000000000",
        "divide 99999999999",
        "divide six",
        "divide -6",
        "divide +6",
        "divide 06",
        "divide 601",
        "divide 3601",
        "divide 6.0",
    ] {
        assert_eq!(say(&mut c, bad), RANGE, "{bad}");
        assert_eq!(c.dividing(), None, "{bad}");
    }
    for bad in ["divide 6 7", "divide stop now"] {
        assert_eq!(say(&mut c, bad), "error: usage: divide <divisions>|stop", "{bad}");
    }
    assert_eq!(say(&mut c, "divide"), "error: not dividing: send divide <divisions> first");
    assert_eq!(say(&mut c, "divide stop"), "error: not dividing: send divide <divisions> first");
    // with a finer encoder, more
    assert_eq!(say(&mut c, "set cpr 14400"), "ok cpr=14400");
    assert!(say(&mut c, "divide 3600").starts_with("ok divide=3600 "));
}

#[test]
fn divide_replies_with_the_readout_and_status_carries_it_while_dividing() {
    let mut c = ctl();
    assert_eq!(
        say(&mut c, "divide 6"),
        "ok divide=6 division=0 division_deg=0.0 to_deg=0.0 to_counts=0.00 within=yes angle_deg=0.0 angle_from=start"
    );
    // the spindle turned by hand 404 counts, past the index at count 5:
    // 399 from it, 59.85 degrees, a count short of division 1
    for k in 1..=404u16 {
        let index = (k == 5).then_some(5);
        c.tick(&TickInput { lathe: k, index, ..TickInput::default() });
    }
    let readout = "divide=6 division=1 division_deg=60.0 to_deg=0.2 to_counts=1.00 within=yes";
    assert_eq!(say(&mut c, "divide"), std::format!("ok {readout} angle_deg=59.9 angle_from=index"));
    let status = say(&mut c, "status");
    assert!(status.ends_with(&std::format!(" indexed=yes angle_deg=59.9 angle_from=index {readout}")), "{status}");
    assert_eq!(say(&mut c, "divide stop"), "ok divide ended");
    let status = say(&mut c, "status");
    assert!(status.ends_with(" indexed=yes angle_deg=59.9 angle_from=index"), "{status}");
}

#[test]
fn while_dividing_engage_check_selftest_and_dfu_are_refused_with_the_reason() {
    let mut c = ctl();
    say(&mut c, "divide 6");
    let dividing = "error: dividing (the chuck is turned by hand, the cutter stays off): divide stop first";
    for cmd in ["engage", "check-encoder start", "selftest start", "dfu"] {
        let (r, a) = handle(cmd.as_bytes(), &mut c);
        assert_eq!((r.as_str(), a), (dividing, Action::None), "{cmd}");
    }
    assert!(say(&mut c, "jog 90").starts_with("ok jogging steps=800"), "a jog goes");
    assert_eq!(say(&mut c, "divide 8"), "error: a jog is running: wait for it to end, or stop");
    assert_eq!(c.dividing(), Some(6));
    let mut c = ctl();
    say(&mut c, "engage");
    assert_eq!(
        say(&mut c, "divide 6"),
        "error: stop first: the cutter is engaged or ramping down (divide only while idle)"
    );
}
