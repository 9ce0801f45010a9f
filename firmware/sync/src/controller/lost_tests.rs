//! The lost-step alarm in the controller: the steps sent (the pulses
//! counted, signed by the books' windows) against a shaft encoder, on the
//! bench's step output (`rig`).

use super::lost::SETTLE_TICKS;
use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;

/// 3 200 steps and a 1 000-count shaft encoder (3.2 steps a count).
fn with_encoder() -> Config {
    Config::default().with("cutter-cpr", "1000").unwrap()
}

/// The shaft encoder's raw count where the cutter has made `net` steps.
fn shaft(net: i64) -> u16 {
    (net * 1000).div_euclid(3200) as u16
}

/// One tick with the shaft where the output's steps put it, less `lag`.
fn follow(r: &mut Rig, speed_q16: i64, lag: i64) -> TickOutput {
    let cutter = shaft(r.cutter_net - lag);
    r.tick_with(speed_q16, TickInput { cutter, ..TickInput::default() })
}

#[test]
fn the_steps_sent_are_the_pulses_counted_with_their_directions() {
    // the lathe forward, and backward: every tick, what the controller
    // counts as sent is what the output made before it, with its sign
    for speed in [per_tick(1.7), per_tick(-1.7)] {
        let mut r = Rig::new(with_encoder());
        r.c.engage().unwrap();
        for _ in 0..3_000 {
            let before = r.cutter_net;
            follow(&mut r, speed, 0);
            assert_eq!(r.c.steps.emitted(), before);
        }
        assert!(r.cutter_net.signum() == speed.signum() && r.cutter_net.abs() > 1_000, "{}", r.cutter_net);
    }
}

#[test]
fn a_shaft_that_follows_never_trips_and_one_that_stops_trips_at_once() {
    let mut r = Rig::new(with_encoder());
    r.c.engage().unwrap();
    for k in 0..3_000 {
        follow(&mut r, per_tick(2.0), 0);
        assert_eq!(r.c.fault(), None, "tick {k}");
    }
    // within one count: |shaft − steps| < 3.2 steps
    let m = r.c.lost_milli_steps().unwrap();
    assert!(m.abs() < 3_200, "{m}");
    // the rotor stops; the steps go on: the fault comes on the first tick
    // the steps sent are more than 32 past the shaft, not before
    let (held, mut before) = (r.cutter_net, 0);
    let mut tripped = None;
    for _ in 0..40 {
        let lag = r.cutter_net - held;
        let out = follow(&mut r, per_tick(2.0), lag);
        let now = r.c.lost_milli_steps().unwrap();
        if r.c.fault() == Some(Fault::LostSteps) {
            tripped = Some((before, now, out));
            break;
        }
        before = now;
    }
    let (before, now, out) = tripped.expect("no lost-steps fault");
    assert!(before <= 32_000 && now > 32_000, "{before} then {now} thousandths of a step");
    assert!(out.halt && !out.enable, "stops at once, as the E-stop");
}

#[test]
fn a_shaft_behind_by_the_limit_is_within_it_and_beyond_it_is_not() {
    for (lag, fault) in [(32 - 4, None), (32 + 4, Some(Fault::LostSteps))] {
        let mut r = Rig::new(with_encoder());
        r.c.engage().unwrap();
        for _ in 0..SETTLE_TICKS + 10 {
            follow(&mut r, per_tick(1.0), 0);
        }
        for _ in 0..50 {
            follow(&mut r, per_tick(1.0), lag);
        }
        assert_eq!(r.c.fault(), fault, "lag {lag}");
    }
}

#[test]
fn the_shaft_turned_by_hand_or_jumping_on_enable_is_no_fault() {
    let mut r = Rig::new(with_encoder());
    // idle, motor off: turned half a turn by hand
    for k in 0..500 {
        r.tick_with(0, TickInput { cutter: (k * 2) as u16, ..TickInput::default() });
    }
    assert_eq!(r.c.fault(), None);
    // energised: the rotor jumps 10 counts (32 steps) to its full step
    r.c.engage().unwrap();
    for _ in 0..SETTLE_TICKS {
        r.tick_with(0, TickInput { cutter: 1010, ..TickInput::default() });
    }
    for _ in 0..100 {
        r.tick_with(0, TickInput { cutter: 1010, ..TickInput::default() });
    }
    assert_eq!(r.c.fault(), None);
    assert_eq!(r.c.lost_milli_steps(), Some(0));
}

#[test]
fn without_a_cutter_encoder_nothing_is_measured_and_status_says_nothing() {
    let mut r = Rig::new(Config::default());
    r.c.engage().unwrap();
    for _ in 0..1_000 {
        r.tick_with(per_tick(2.0), TickInput { cutter: 0, ..TickInput::default() });
    }
    assert_eq!(r.c.fault(), None);
    assert_eq!(r.c.lost_milli_steps(), None);
    let mut out = crate::console::Reply::new();
    crate::console::status_line(&r.c, &mut out);
    assert!(!out.contains("shaft_err_steps"), "{out}");
    // a BLDC's encoder is its position, not a shaft against steps
    let mut b = Rig::new(with_encoder().with("drive", "bldc").unwrap());
    b.tick(0);
    assert_eq!(b.c.lost_milli_steps(), None);
}

#[test]
fn status_shows_the_shaft_against_the_steps_sent() {
    let mut r = Rig::new(with_encoder());
    r.c.engage().unwrap();
    for _ in 0..SETTLE_TICKS + 100 {
        follow(&mut r, per_tick(1.0), 0);
    }
    for _ in 0..20 {
        follow(&mut r, per_tick(1.0), 16);
    }
    let m = r.c.lost_milli_steps().unwrap();
    assert!((12_800..=19_200).contains(&m), "16 steps behind, within a count: {m}");
    let mut out = crate::console::Reply::new();
    crate::console::status_line(&r.c, &mut out);
    let want = std::format!(" shaft_err_steps={}.{:03}", m / 1000, m % 1000);
    assert!(out.contains(&want), "{out}");
    // and ahead of them: negative
    for _ in 0..20 {
        follow(&mut r, per_tick(1.0), -16);
    }
    let m = r.c.lost_milli_steps().unwrap();
    assert!((-19_200..=-12_800).contains(&m), "16 steps ahead, within a count: {m}");
}
