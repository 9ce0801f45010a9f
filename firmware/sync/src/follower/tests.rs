use super::*;
use proptest::prelude::*;

fn limits(v_steps: f64, a_steps: f64) -> Limits {
    Limits { max_velocity: (v_steps * 65536.0) as i64, max_accel: (a_steps * 65536.0) as i64, start_velocity: 0 }
}

proptest! {
    #[test]
    fn never_exceeds_rate_or_acceleration(
        vmax in 0.5f64..8.0, amax in 0.0005f64..0.05,
        start in -100_000i64..100_000, tv in -7.0f64..7.0,
        ticks in 100usize..3000,
    ) {
        let lim = limits(vmax, amax);
        let mut f = Follower::default();
        let (mut target, tvq) = (start << 16, (tv * 65536.0) as i64);
        for _ in 0..ticks {
            let before = f.velocity;
            target += tvq;
            f.track(target, tvq, &lim);
            prop_assert!(f.velocity.abs() <= lim.max_velocity);
            prop_assert!((f.velocity - before).abs() <= lim.max_accel);
        }
    }

    #[test]
    fn catches_up_to_a_moving_target_and_holds_it(
        start in -20_000i64..20_000, tv in -3.0f64..3.0,
    ) {
        // Engage while spinning: the follower starts at rest, the target
        // runs away at tv; within the time the limits allow it must lock.
        let lim = limits(6.0, 0.01);
        let mut f = Follower::default();
        let tvq = (tv * 65536.0) as i64;
        let mut target = start << 16;
        let mut locked_at = None;
        for k in 0..40_000 {
            target += tvq;
            f.track(target, tvq, &lim);
            let e = (target - f.position).abs();
            if e < 1 << 15 && (f.velocity - tvq).abs() < lim.max_accel {
                locked_at.get_or_insert(k);
            } else if locked_at.is_some() {
                prop_assert!(e < 1 << 16, "lost lock at {k}: error {e}");
            }
        }
        // Bound: accelerate to tv, make up the gap at 6 steps/tick: generous 3×.
        let gap = start.unsigned_abs() as f64 + 1.0;
        let bound = 3.0 * (2.0 * (6.0 / 0.01) + gap / 3.0) + 200.0;
        prop_assert!(locked_at.is_some_and(|k| (k as f64) < bound), "{locked_at:?} vs {bound}");
    }
}

#[test]
fn braking_keeps_the_overshoot_under_a_step() {
    let lim = limits(8.0, 0.002);
    let mut f = Follower::default();
    let target = 50_000i64 << 16;
    let mut worst_over = 0;
    for _ in 0..60_000 {
        f.track(target, 0, &lim);
        worst_over = worst_over.max(f.position - target);
    }
    assert!(worst_over < 1 << 16, "overshoot {} steps", worst_over as f64 / 65536.0);
    assert_eq!(f.whole_steps(), 50_000);
}

#[test]
fn ramp_down_stops_within_the_acceleration_limit() {
    let lim = limits(8.0, 0.01);
    let mut f = Follower { position: 0, velocity: 5 << 16 };
    let mut ticks = 0;
    while f.velocity != 0 {
        let v = f.velocity;
        f.ramp_down(&lim);
        assert!((v - f.velocity).abs() <= lim.max_accel);
        ticks += 1;
        assert!(ticks < 1 << 20, "never stops"); // (a bounded test)
    }
    let a = lim.max_accel;
    assert_eq!(ticks as i64, ((5 << 16) + a - 1) / a);
}

proptest! {
    /// With a start rate, a change of speed beyond `max_accel` is at most
    /// the start rate, between two speeds within it; ramping down keeps to
    /// `max_accel`.
    #[test]
    fn only_speeds_within_the_start_rate_change_at_once(
        vmax in 0.5f64..8.0, amax in 0.0005f64..0.05, startv in 0.01f64..0.5,
        start in -100_000i64..100_000, tv in -7.0f64..7.0, ticks in 100usize..3000,
    ) {
        let lim = Limits { start_velocity: (startv * 65536.0) as i64, ..limits(vmax, amax) };
        let mut f = Follower::default();
        let (mut target, tvq) = (start << 16, (tv * 65536.0) as i64);
        for k in 0..ticks {
            let before = f.velocity;
            target += tvq;
            let tracking = k % 500 < 250;
            if tracking { f.track(target, tvq, &lim) } else { f.ramp_down(&lim) }
            let (s, dv) = (lim.start_velocity, (f.velocity - before).abs());
            let within = tracking && before.abs() <= s && f.velocity.abs() <= s && dv <= s;
            prop_assert!(within || dv <= lim.max_accel, "{before} -> {}", f.velocity);
        }
    }
}

/// A lathe that starts from rest: with a start rate the follower takes the
/// target's speed at once and lags it by no more than the pull closes;
/// without, it catches up at `max_accel` and lags far more. Ramping down
/// from within the start rate stops at once.
#[test]
fn a_start_rate_takes_a_slow_targets_speed_at_once() {
    let slow = limits(6.0, 0.0005);
    let lim = Limits { start_velocity: 1 << 14, ..slow }; // a quarter step a tick
    let lag = |lim: &Limits| {
        let mut f = Follower::default();
        let (mut target, tv) = (1 << 16, 1 << 13); // an eighth of a step a tick
        let mut worst = 0;
        for _ in 0..2000 {
            target += tv;
            f.track(target, tv, lim);
            worst = worst.max(target - f.position);
        }
        (worst, f)
    };
    let ((with, mut f), (without, _)) = (lag(&lim), lag(&slow));
    assert!(with <= 1 << 16, "with: {with}");
    assert!(without > 3 * with, "without {without} against with {with}");
    let v = f.velocity;
    f.ramp_down(&lim);
    assert_eq!(f.velocity, v - slow.max_accel, "a stop ramps at max-accel, start rate or not");
}

/// The band is for changes within the start rate between speeds within
/// it: from 0.8 S a pull of +0.5 S would leave it, and from +S a pull to
/// −S would reverse by 2 S; both keep to `max_accel`.
#[test]
fn no_change_leaves_the_start_rate_or_reverses_across_it_at_once() {
    let s = 1 << 14;
    let lim = Limits { start_velocity: s, ..limits(6.0, 0.0005) };
    let pull = |v: i64, want: i64| {
        // the target at our speed, `16 · want` ahead: the pull is 1/16 of it
        let mut f = Follower { position: 0, velocity: v };
        f.track(v + 16 * want, v, &lim);
        f.velocity - v
    };
    assert_eq!(pull(s * 8 / 10, s / 2), lim.max_accel, "would leave the band");
    assert_eq!(pull(s, -2 * s), -lim.max_accel, "a reversal across it");
    assert_eq!(pull(s / 4, s / 2), s / 2, "within it: at once");
}

/// The start rate in Q16 steps a tick, rounded down: 3 200 steps/s at
/// 25 kHz is 0.128 step a tick; the other limits as they were.
#[test]
fn the_start_rate_becomes_steps_a_tick_rounded_down() {
    let lim = Limits::from_rates(200_000, 400_000, 25_000);
    let started = lim.with_start(3_200, 25_000);
    assert_eq!(started.start_velocity, 8_388, "0.128 × 65 536 = 8 388.6");
    assert_eq!(Limits { start_velocity: 0, ..started }, lim);
    assert_eq!(lim.with_start(1, 25_000).start_velocity, 2, "65 536 / 25 000");
    assert_eq!(lim.with_start(0, 25_000).start_velocity, 0);
}
