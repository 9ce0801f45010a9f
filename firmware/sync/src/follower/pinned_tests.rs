//! Fixed cases of the follower's law: moving away from its target it takes
//! the pull's speed (the braking rule is for closing in), and a move from
//! rest to rest is close to the fastest the limits allow (it brakes at the
//! stopping distance v²/2a, not before).

use super::*;

#[test]
fn moving_away_from_the_target_the_speed_is_feed_forward_plus_the_pull() {
    // 30/65536 step a tick past a target 5/65536 behind: within one tick's
    // acceleration of it, the new speed is the target's (0) plus
    // floor(−5/16) = −1, not merely a stop
    let lim = Limits { max_velocity: 1 << 20, max_accel: 41, start_velocity: 0 };
    let mut f = Follower { position: 0, velocity: 30 };
    f.track(-5, 0, &lim);
    assert_eq!((f.position, f.velocity), (-1, -1));
    // the same, following a target moving at 100
    let mut f = Follower { position: 0, velocity: 130 };
    f.track(95, 100, &lim);
    assert_eq!((f.position, f.velocity), (99, 99));
}

#[test]
fn a_move_from_rest_to_rest_takes_within_five_percent_of_the_bang_bang_time() {
    // 8 steps a tick and 41/65536 step a tick² (the defaults): accelerate
    // half way, brake the other half: 2·√(d/a) ticks (and under a hundred
    // more for the pull's last half step)
    let lim = Limits { max_velocity: 8 << 16, max_accel: 41, start_velocity: 0 };
    for steps in [1_000i64, 10_000, 50_000] {
        let target = steps << 16;
        let mut f = Follower::default();
        let mut ticks = 0u32;
        while !f.arrived(target, 0, &lim) {
            f.track(target, 0, &lim);
            ticks += 1;
            assert!(ticks < 100_000);
        }
        let fastest = 2.0 * (target as f64 / lim.max_accel as f64).sqrt();
        assert!((ticks as f64) < fastest * 1.05, "{steps} steps: {ticks} ticks, fastest {fastest:.0}");
    }
}

#[test]
fn arrived_means_under_half_a_step_away_and_within_four_ticks_acceleration_of_speed() {
    let lim = Limits { max_velocity: 8 << 16, max_accel: 41, start_velocity: 0 };
    let at = |position: i64, velocity: i64| Follower { position, velocity };
    // position: half a step either side is not there yet
    assert!(at(1_000 + (1 << 15) - 1, 100).arrived(1_000, 100, &lim));
    assert!(at(1_000 - (1 << 15) + 1, 100).arrived(1_000, 100, &lim));
    assert!(!at(1_000 + (1 << 15), 100).arrived(1_000, 100, &lim));
    assert!(!at(1_000 - (1 << 15), 100).arrived(1_000, 100, &lim));
    // speed: 4 × 41 either side is, a unit more is not
    assert!(at(1_000, 100 + 164).arrived(1_000, 100, &lim));
    assert!(at(1_000, 100 - 164).arrived(1_000, 100, &lim));
    assert!(!at(1_000, 100 + 165).arrived(1_000, 100, &lim));
    assert!(!at(1_000, 100 - 165).arrived(1_000, 100, &lim));
}
