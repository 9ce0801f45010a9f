//! The gear target to a 65536th of a step: the exact rounded steps plus
//! the rounding remainder, the phase offset with its sign, half-step ties
//! in both directions; the plausible jump; startup on any counter values.

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;

/// Idle with the lathe at rest (the estimator's offset snapped to 0) and
/// no step made, the phase error is the whole target: (count × num/den
/// steps + phase) in Q16.
fn at_rest_on(config: Config, count: i64) -> Rig {
    let mut r = Rig::new(config);
    let dir = count.signum();
    for _ in 0..count.abs() {
        r.tick(per_tick(dir as f64));
    }
    r.run(0, (Timing::FIRMWARE.tick_hz / 8) as usize); // over 0.1 s without a count: at rest
    assert!(r.c.lathe_at_rest());
    assert_eq!(r.c.status().cutter_steps, 0);
    r
}

#[test]
fn at_rest_the_target_carries_the_gears_remainder_to_a_65536th_of_a_step() {
    // 8/3 steps a count (den 3: the remainder is never a whole 65536th,
    // so the target is the exact value floored)
    for count in [-5i64, -2, -1, 1, 2, 4, 7] {
        let r = at_rest_on(Config::default(), count);
        let exact = (count as i128 * 8 * 65536).div_euclid(3) as i64;
        assert_eq!(r.c.status().phase_error_q16, exact, "count {count}");
        // the whole steps are the rounding of the same value
        assert_eq!(r.c.status().target_steps, (exact + (1 << 15)) >> 16, "count {count}");
    }
}

#[test]
fn idle_with_the_lathe_turning_the_phase_error_is_the_gear_now_not_ahead() {
    // one count a tick: the estimator's sub-count offset settles to 0, so
    // the target now is exactly count × 8/3 (the prediction to the end of
    // the step output's window is taken out again)
    let mut r = Rig::new(Config::default());
    r.run(per_tick(1.0), 5_000);
    for _ in 0..100 {
        r.tick(per_tick(1.0));
        let exact = (r.lathe() as i128 * 8 * 65536).div_euclid(3) as i64;
        assert_eq!(r.c.status().phase_error_q16, exact, "at {}", r.lathe());
    }
}

#[test]
fn a_negative_phase_offset_moves_the_target_back() {
    // −90° of a 3200-step cutter is −800 steps
    let c = Config::default().with("phase", "-90").unwrap();
    let r = at_rest_on(c, 0);
    assert_eq!(r.c.status().phase_error_q16, -800 << 16);
    let c = Config::default().with("phase", "22.5").unwrap();
    let r = at_rest_on(c, 3);
    assert_eq!(r.c.status().phase_error_q16, (200 << 16) + (8 << 16), "22.5° is 200 steps, 3 counts 8");
}

/// 2400 counts, 1200 steps, ratio 1: half a step a count, so every odd
/// count is an exact tie, rounded half up (toward +∞) either way.
fn half_step() -> Config {
    Config { motor_steps_per_rev: 1_200, ratio: crate::Ratio::new(1, 1).unwrap(), ..Config::default() }
}

#[test]
fn half_step_ties_round_up_moving_backwards_as_forwards() {
    let mut r = Rig::new(half_step());
    for count in (-7i64..=0).rev() {
        // count/2 rounded half up: −½ → 0, −1½ → −1, −2½ → −2 ...
        let want = (count + 1).div_euclid(2);
        assert_eq!(r.c.status().target_steps, want, "count {count} going back");
        r.tick(per_tick(-1.0));
    }
    for count in -8i64..=7 {
        assert_eq!(r.c.status().target_steps, (count + 1).div_euclid(2), "count {count} going forward");
        r.tick(per_tick(1.0));
    }
}

#[test]
fn at_a_tie_the_target_is_half_a_step_below_the_rounded_steps() {
    for count in [-3i64, -1, 1, 3] {
        let r = at_rest_on(half_step(), count);
        assert_eq!(r.c.status().phase_error_q16, count << 15, "count {count}");
    }
}

#[test]
fn a_jump_of_max_counts_per_tick_is_plausible_and_one_more_is_not() {
    // max-rpm 1500 at 2400 counts is 3 counts a tick at 20 kHz; with 25 %
    // margin and 2 counts of jitter allowance, 6
    let mut r = Rig::new(Config::default());
    let most = r.c.derived().max_counts_per_tick as f64;
    let tick_hz = Timing::FIRMWARE.tick_hz as f64;
    assert_eq!(most, (1_500.0 * 2_400.0 / 60.0 / tick_hz * 1.25).ceil() + 2.0);
    r.tick(per_tick(most));
    r.tick(per_tick(-most));
    assert_eq!(r.c.fault(), None);
    r.tick(per_tick(most + 1.0));
    assert_eq!(r.c.fault(), Some(Fault::EncoderImplausible));
    let mut r = Rig::new(Config::default());
    r.tick(per_tick(-most - 1.0));
    assert_eq!(r.c.fault(), Some(Fault::EncoderImplausible));
}

#[test]
fn the_controller_starts_on_whatever_the_counters_hold() {
    for drive in [DriveKind::Stepper, DriveKind::Bldc] {
        let mut c = Controller::new(Config { drive, ..Config::default() }, Timing::FIRMWARE);
        c.start(40_000, 30_000, 20_000);
        let io = TickInput { lathe: 40_000, emitted: 30_000, cutter: 20_000, ..TickInput::default() };
        c.tick(&io);
        assert_eq!(c.fault(), None, "{drive:?}: no jump, no unplanned pulses");
        let s = c.status();
        assert_eq!((s.lathe_counts, s.cutter_steps, s.target_steps), (0, 0, 0), "{drive:?}");
        // a count on from there is a count
        c.tick(&TickInput { lathe: 40_001, cutter: 20_003, ..io });
        assert_eq!(c.status().lathe_counts, 1);
        if drive == DriveKind::Bldc {
            assert_eq!(c.status().cutter_steps, 3, "the cutter's encoder, from its start");
        }
    }
}

#[test]
fn the_lathe_is_at_rest_only_after_a_tenth_of_a_second_without_a_count() {
    let mut r = Rig::new(Config::default());
    assert!(r.c.lathe_at_rest(), "before the first tick nothing has moved");
    r.run(per_tick(0.5), 1_000);
    assert!(!r.c.lathe_at_rest(), "turning");
    // a tenth of a second's ticks without a count
    let tenth = (Timing::FIRMWARE.tick_hz / 10) as usize;
    r.run(0, tenth - 2);
    assert!(!r.c.lathe_at_rest());
    r.run(0, 2);
    assert!(r.c.lathe_at_rest());
}
