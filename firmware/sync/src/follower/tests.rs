use super::*;
use proptest::prelude::*;

fn limits(v_steps: f64, a_steps: f64) -> Limits {
    Limits { max_velocity: (v_steps * 65536.0) as i64, max_accel: (a_steps * 65536.0) as i64 }
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
