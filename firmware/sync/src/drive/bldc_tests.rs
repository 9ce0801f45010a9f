//! The BLDC speed loop: feed-forward plus PI on the cutter encoder's phase
//! error, its output limit, anti-windup, standstill hold and stall check.
//! Default settings with drive=bldc: max-rate 200 kHz is `MAX_Q16` a
//! tick (10 counts at 20 kHz, 655 360 in Q16), so the output limit is
//! `UMAX` (1½ × that); a stall is `STALL` ticks (0.2 s) commanded to move
//! with the encoder still.

use super::*;
use crate::config::{Config, DriveKind};
use crate::derived::Derived;
use crate::timing::Timing;

const TICK_HZ: i64 = Timing::FIRMWARE.tick_hz as i64;
/// max-rate's default, Q16 counts a tick.
const MAX_Q16: i64 = (200_000 << 16) / TICK_HZ;
const UMAX: i64 = MAX_Q16 * 3 / 2;
/// 0.2 s of ticks.
const STALL: i64 = TICK_HZ / 5;
/// The default `bldc-tau` (20 ms), in ticks: the feed-forward's lead.
const TAU: i64 = TICK_HZ / 50;

fn derived() -> Derived {
    let d = Derived::new(&Config { drive: DriveKind::Bldc, ..Config::default() }, Timing::FIRMWARE);
    assert_eq!((d.limits.max_velocity, d.stall_ticks as i64, d.bldc.tau_ticks), (MAX_Q16, STALL, TAU));
    d
}

fn moving(position: i64, velocity: i64) -> Follower {
    Follower { position, velocity }
}

/// The integral term as it stands: a command at one Q16 count a tick (the
/// wired way) with
/// no phase error and no change of speed is 1 + integral (and integrates
/// nothing).
fn integral(b: &mut Bldc, d: &Derived) -> i64 {
    // (turning the wired way: the command has that sign)
    let v = if d.sense_positive { 1 } else { -1 };
    b.command(&moving(0, v), 0, d);
    b.command(&moving(0, v), 0, d).0 as i64 - v
}

/// A drive that takes 4096 / 65 536 of the error a tick and 2^-10 of it
/// into the integral (fixed gains, whatever the drive), with no lag.
fn stiff() -> Derived {
    let mut d = derived();
    d.bldc = BldcGains { kp_q16: 4_096, ki_q32: 1 << 22, tau_ticks: 0, kv_q8: 0, rate_shift: 0 };
    d
}

#[test]
fn the_command_is_feed_forward_plus_the_errors_share_plus_its_integral() {
    let d = stiff();
    let mut b = Bldc::default();
    b.command(&moving(0, 3_000), 0, &d);
    // 100 counts behind (Q16 6 553 600): 409 600 + 6 400 integrated, on
    // 3000 of feed-forward
    assert_eq!(b.command(&moving(100 << 16, 3_000), 0, &d), (3_000 + 409_600 + 6_400, false));
    assert_eq!(b.command(&moving(100 << 16, 3_000), 0, &d), (3_000 + 409_600 + 12_800, false));
    assert_eq!(integral(&mut b, &d), 12_800);
    // and ahead of the command the other way, on a cutter wired to turn
    // the other way (`dir opposite`)
    let d = wired(stiff(), -1);
    let mut b = Bldc::default();
    b.command(&moving(0, -3_000), 0, &d);
    assert_eq!(b.command(&moving(0, -3_000), 16 << 16, &d), (-3_000 - 65_536 - 1_024, false));
}

/// `d` for a cutter wired to turn the core's positive way (`dir same`,
/// `sign` 1) or the other.
fn wired(mut d: Derived, sign: i64) -> Derived {
    d.sense_positive = sign > 0;
    d
}

#[test]
fn a_command_against_the_wired_sense_is_0_winds_nothing_up_and_never_stalls() {
    let d = stiff();
    let mut b = Bldc::default();
    // at rest, 10 counts ahead: the loop would reverse the cutter, which no
    // interface can; the command is 0 (saturated), nothing integrates
    for k in 0..10_000 {
        assert_eq!(b.command(&moving(0, 0), 10 << 16, &d), (0, false), "tick {k}");
    }
    assert_eq!(integral(&mut b, &d), 0);
    let d = wired(stiff(), -1);
    let mut b = Bldc::default();
    assert_eq!(b.command(&moving(10 << 16, 0), 0, &d), (0, false), "dir opposite: behind is the other way");
}

#[test]
fn the_gains_are_the_drives() {
    // esc50, τ 20 ms (`gains`) at 20 kHz: the hold 201 ticks, the filter
    // 256 (a frame is 400); Kv = 400 / 914 (112 / 256), τ' 278, ω_c =
    // 32 768 / 735 = 44, Kp = 44 × 368 / 256 = 63; Ki 63 × 44 / 4 = 693
    assert_eq!(TICK_HZ, 20_000, "the figures below are the board's");
    let d = derived();
    let g = BldcGains { kp_q16: 63, ki_q32: 693, tau_ticks: 400, kv_q8: 112, rate_shift: 8 };
    assert_eq!(d.bldc, g);
    let mut b = Bldc::default();
    b.command(&moving(0, 0), 0, &d);
    // a step of 100 counts: its rate is 1/256 of it at once
    let e = 100i64 << 16;
    let rate = e >> 8;
    let want = ((e * g.kp_q16) >> 16) + ((rate * g.kv_q8) >> 8) + ((e * g.ki_q32) >> 32);
    assert_eq!(b.command(&moving(e, 0), 0, &d).0 as i64, want);
    // held: the rate decays by 1/256 a tick, the integral grows
    let rate = rate - (rate >> 8);
    let want = ((e * g.kp_q16) >> 16) + ((rate * g.kv_q8) >> 8) + ((2 * e * g.ki_q32) >> 32);
    assert_eq!(b.command(&moving(e, 0), 0, &d).0 as i64, want);
}

#[test]
fn a_change_of_speed_is_fed_forward_times_the_drives_lag_within_max_accel() {
    let d = derived();
    let a = d.limits.max_accel;
    let mut b = Bldc::default();
    assert_eq!(b.command(&moving(0, 0), 0, &d).0, 0);
    // speeding up by half the limit: τ's ticks of it ahead
    assert_eq!(b.command(&moving(0, a / 2), 0, &d).0 as i64, a / 2 + TAU * (a / 2));
    // steady: only the speed
    assert_eq!(b.command(&moving(0, a / 2), 0, &d).0 as i64, a / 2);
    // a jump (a start rate) counts as the limit, not as one tick's spike
    assert_eq!(b.command(&moving(0, 100 * a), 0, &d).0 as i64, 100 * a + TAU * a);
    assert_eq!(b.command(&moving(0, 0), 0, &d).0 as i64, 0, "slowing to rest");
}

#[test]
fn the_command_is_limited_to_one_and_a_half_times_max_rate() {
    for sign in [1, -1] {
        let d = wired(derived(), sign);
        let mut b = Bldc::default();
        let (u, _) = b.command(&moving(sign * (10_000 << 16), sign * MAX_Q16), 0, &d);
        assert_eq!(u as i64, sign * UMAX);
    }
}

#[test]
fn an_error_pushing_a_saturated_command_further_is_not_integrated() {
    for sign in [1, -1] {
        let d = wired(stiff(), sign);
        let mut b = Bldc::default();
        for _ in 0..100 {
            let (u, _) = b.command(&moving(sign * (100 << 16), sign * MAX_Q16), 0, &d);
            assert_eq!(u as i64, sign * UMAX);
        }
        assert_eq!(integral(&mut b, &d), 0, "no wind-up ({sign})");
    }
}

#[test]
fn an_error_pulling_a_saturated_command_back_is_integrated() {
    let d = stiff();
    let mut b = Bldc::default();
    // wind the integral up within the limit: 391 ticks of 16 counts behind
    for _ in 0..391 {
        let (u, _) = b.command(&moving(16 << 16, 0), 0, &d);
        assert!((u as i64) < UMAX);
    }
    assert_eq!(integral(&mut b, &d), 391 * 1_024);
    // at full speed and a count ahead, the sum is over the limit, but the
    // error says slow down: the integral unwinds (by 65 536 >> 10 = 64)
    b.command(&moving(0, MAX_Q16), 0, &d);
    let (u, _) = b.command(&moving(0, MAX_Q16), 1 << 16, &d);
    assert_eq!(u as i64, UMAX);
    assert_eq!(integral(&mut b, &d), 391 * 1_024 - 64);
}

#[test]
fn standing_on_the_commanded_count_the_command_is_zero_and_nothing_integrates() {
    let d = stiff();
    let mut b = Bldc::default();
    b.command(&moving(16 << 16, 0), 0, &d); // integral 1024
                                            // at rest 0.3 count past count 10, the encoder on 10: hold, no hunting
    let here = moving((10 << 16) + 19_660, 0);
    for _ in 0..10 {
        assert_eq!(b.command(&here, 10 << 16, &d), (0, false));
    }
    assert_eq!(integral(&mut b, &d), 1_024);
    // at rest but a count off: the loop acts
    assert_ne!(b.command(&moving(11 << 16, 0), 10 << 16, &d).0, 0);
    // on the count but commanded to move: feed-forward
    let mut b = Bldc::default();
    b.command(&moving(10 << 16, 5_000), 10 << 16, &d);
    assert_eq!(b.command(&moving(10 << 16, 5_000), 10 << 16, &d), (5_000, false));
}

#[test]
fn a_cutter_still_for_more_than_stall_ticks_while_commanded_to_move_stalls() {
    let d = stiff();
    // a sixteenth of max-rate is enough to expect the encoder to move
    let v = MAX_Q16 / 16;
    let mut b = Bldc::default();
    for k in 1..=STALL {
        assert_eq!(b.command(&moving(0, v), 0, &d), (v as i32, false), "tick {k}");
    }
    assert_eq!(b.command(&moving(0, v), 0, &d), (v as i32, true), "tick {}", STALL + 1);
    // slower, it is not judged
    let mut b = Bldc::default();
    for _ in 0..STALL + 1_000 {
        assert!(!b.command(&moving(0, v - 1), 0, &d).1);
    }
}

#[test]
fn any_encoder_count_restarts_the_stall_check() {
    let d = stiff();
    let mut b = Bldc::default();
    let every = STALL * 4 / 5;
    for k in 1..=3 * every {
        let cutter = (k / every) << 16; // a count every 4/5 of the stall's ticks
        assert!(!b.command(&moving(cutter, 100_000), cutter, &d).1, "tick {k}");
    }
}

#[test]
fn reset_clears_the_integral_and_the_stall_count() {
    let d = stiff();
    let mut b = Bldc::default();
    let most = STALL * 4 / 5;
    for _ in 0..most {
        b.command(&moving(16 << 16, 100_000), 0, &d);
    }
    b.reset();
    for k in 0..most {
        // (no phase error: nothing integrates)
        assert!(!b.command(&moving(0, 100_000), 0, &d).1, "{k}: more than a stall's ticks, but reset between");
    }
    assert_eq!(integral(&mut b, &d), 0);
}

#[test]
fn the_cutter_encoder_counts_from_where_it_started() {
    let mut b = Bldc::default();
    b.start(40_000);
    assert_eq!(b.read(40_000), 0);
    assert_eq!(b.read(40_010), 10);
    assert_eq!(b.read(39_990), -10);
}

#[test]
fn after_a_reset_the_next_run_takes_no_rate_or_acceleration_from_the_last() {
    let d = derived();
    let a = d.limits.max_accel;
    let mut b = Bldc::default();
    // a run at speed, 100 counts behind, then a fault's reset
    for _ in 0..100 {
        b.command(&moving(100 << 16, 300_000), 0, &d);
    }
    b.reset();
    // from rest again: the speed's change counts from 0, not from 300 000
    // (which would be a full deceleration, the command clamped to 0), and
    // no rate is left from the old error
    let v = a / 2;
    assert_eq!(b.command(&moving(0, v), 0, &d).0 as i64, v + TAU * v);
}
