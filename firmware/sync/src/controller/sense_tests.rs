//! `dir=opposite` through the controller: the gear counts the other way,
//! re-bases the other way, and the cutter turns the other way; the X cam
//! follows the lathe's angle whatever the sense.

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::{Config, Sense};
use crate::gear::Scale;

fn opposite() -> Config {
    Config { sense: Sense::Opposite, ..Config::default() }
}

#[test]
fn with_dir_opposite_the_gear_counts_down_as_the_lathe_counts_up() {
    for (sense, want) in [(Sense::Same, 800), (Sense::Opposite, -800)] {
        let mut r = Rig::new(Config { sense, ..Config::default() });
        // 300 counts × 8/3 = 800 steps
        r.run(per_tick(1.0), 300);
        assert_eq!(r.c.status().target_steps, want, "{sense:?}");
    }
}

#[test]
fn with_dir_opposite_clearing_rebases_the_gear_the_other_way() {
    let mut r = Rig::new(opposite());
    r.tick(per_tick(1000.0)); // an implausible jump
    assert_eq!(r.c.fault(), Some(Fault::EncoderImplausible));
    r.c.clear();
    // −1000 × 8/3 = −2666.7: −2667
    assert_eq!(r.c.status().target_steps, Scale::round(r.c.derived().scale, -1000));
    assert_eq!(r.c.status().target_steps, -2667);
}

#[test]
fn with_dir_opposite_the_first_index_rebases_the_gear_the_other_way() {
    let mut r = Rig::new(opposite());
    for k in 1..=150i64 {
        let index = (k == 100).then_some(100u16);
        r.tick_with(per_tick(1.0), TickInput { index, ..TickInput::default() });
    }
    r.c.service();
    // 50 counts past the index: −133.3 steps
    assert_eq!((r.c.gear_origin(), r.c.status().target_steps), (100, -133));
}

#[test]
fn with_dir_opposite_the_engaged_cutter_steps_backwards() {
    for (sense, want) in [(Sense::Same, 800), (Sense::Opposite, -800)] {
        let mut r = Rig::new(Config { sense, ..Config::default() });
        r.c.engage().unwrap();
        r.run(per_tick(1.0 / 16.0), 4_800); // 300 counts at 39 rpm
        r.run(0, 20_000); // the lathe stops, the cutter settles
        assert_eq!(r.c.state(), State::Synced);
        assert_eq!(r.cutter_net, want, "{sense:?}: the steps the output made, signed by DIR");
        assert_eq!(r.c.status().cutter_steps, want);
    }
}

/// Two controllers on the same lathe, one of each sense, each with an X
/// axis on a cam of one X step per lathe count; no cutter.
fn x_rig(sense: Sense) -> Rig {
    static TABLE: [i32; 2] = [0, 1_200];
    let mut r = Rig::new(Config { sense, drive: DriveKind::None, ..Config::default() });
    let cam = crate::cam::Cam::new(&TABLE, 2_400).unwrap();
    let limits = crate::follower::Limits::from_rates(50_000, 10_000_000, Timing::FIRMWARE.tick_hz as u64);
    r.c.set_x_axis(Some(XAxis::new(cam, limits))).unwrap();
    r
}

#[test]
fn the_x_cam_follows_the_lathes_angle_whatever_the_sense() {
    let (mut same, mut opp) = (x_rig(Sense::Same), x_rig(Sense::Opposite));
    same.c.engage().unwrap();
    opp.c.engage().unwrap();
    // a third of a count a tick: the sub-count interpolation is never 0
    let mut worst = 0;
    for k in 0..1_000 {
        same.tick(per_tick(1.0 / 3.0));
        opp.tick(per_tick(1.0 / 3.0));
        let (a, b) = (same.c.x_axis().unwrap().position_q16(), opp.c.x_axis().unwrap().position_q16());
        if k > 200 {
            worst = worst.max((a - b).abs());
        }
    }
    assert_eq!((same.c.fault(), opp.c.fault()), (None, None));
    // X is 1 step a count: ~330 steps by now
    let x = same.c.x_axis().unwrap().position_q16() >> 16;
    assert!((320..340).contains(&x), "{x}");
    // the two estimates of the sub-count offset differ only in rounding
    // (their shifts floor), far less than the offset itself (a third of a
    // count, here a third of a step)
    assert!(worst < 1 << 10, "differ by {worst} / 65536 step");
}

#[test]
fn with_dir_opposite_the_status_shows_the_lathe_turning_forward_as_it_does() {
    let speed = |sense| {
        let mut r = Rig::new(Config { sense, ..Config::default() });
        r.run(per_tick(1.0), 3_000);
        r.c.status().lathe_velocity_q32
    };
    // one count a tick (2^32 in Q32, to the estimator's rounding) both ways
    for sense in [Sense::Same, Sense::Opposite] {
        let v = speed(sense);
        assert!((v - (1 << 32)).abs() < 1 << 12, "{sense:?}: {v}");
    }
}
