use super::*;
use crate::config::Config;
use crate::gear::Scale;

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

#[test]
fn an_implausible_jump_faults_and_clearing_rebases_the_gear_on_the_counter() {
    let mut c = ctl();
    c.tick(&TickInput { lathe: 1000, ..TickInput::default() });
    assert_eq!(c.state(), State::Fault(Fault::EncoderImplausible));
    c.clear();
    assert_eq!(c.state(), State::Idle);
    let d = c.derived().scale;
    assert_eq!(c.status().target_steps, Scale::round(d, 1000), "gear follows the counter again");
}

#[test]
fn an_implausible_jump_moves_the_gear_by_the_most_a_tick_counts_and_no_more() {
    for jump in [1000i32, -1000] {
        let mut c = ctl();
        c.tick(&TickInput { lathe: jump as u16, ..TickInput::default() });
        assert_eq!(c.state(), State::Fault(Fault::EncoderImplausible));
        let (d, max) = (c.derived().scale, c.derived().max_counts_per_tick as i64);
        assert_eq!(c.status().target_steps, Scale::round(d, max * jump.signum() as i64), "jump {jump}");
    }
}

#[test]
fn estop_and_alarm_halt_at_once_and_drop_enable() {
    for (estop, alarm, fault) in [(true, false, Fault::EStop), (false, true, Fault::DriveAlarm)] {
        let mut c = ctl();
        c.engage().unwrap();
        let out = c.tick(&TickInput { estop_open: estop, alarm, ..TickInput::default() });
        assert_eq!(c.state(), State::Fault(fault));
        assert!(out.halt && !out.enable && out.plan.count == 0);
        assert_eq!(c.engage(), Err(Refusal::Faulted));
    }
}

#[test]
fn enable_is_off_when_idle_and_on_while_engaged() {
    let mut c = ctl();
    assert!(!c.tick(&TickInput::default()).enable);
    c.engage().unwrap();
    assert!(c.tick(&TickInput::default()).enable);
}

#[test]
fn an_estop_during_a_ramped_fault_still_stops_at_once() {
    let mut c = ctl();
    c.engage().unwrap();
    c.trip(Fault::FollowingError);
    let out = c.tick(&TickInput { estop_open: true, ..TickInput::default() });
    assert_eq!(c.state(), State::Fault(Fault::EStop), "the e-stop takes over");
    assert!(out.halt && !out.enable);
    // ...but a ramped fault never replaces an immediate one.
    c.trip(Fault::Overspeed);
    assert_eq!(c.state(), State::Fault(Fault::EStop));
}

fn lathe(raw: u16) -> TickInput {
    TickInput { lathe: raw, ..TickInput::default() }
}

#[test]
fn a_lathe_turned_far_during_a_save_stall_is_no_fault_and_the_reply_says_so() {
    let mut c = ctl();
    c.begin_stall();
    c.tick(&lathe(30_000)); // the first tick after a 2 s erase
    assert_eq!(c.state(), State::Idle, "no encoder-implausible");
    assert_eq!(c.end_stall(), Stall::Lost { reindexed: false });
    let d = c.derived().scale;
    assert_eq!(c.status().target_steps, Scale::round(d, 30_000), "gear re-based on the counter");
    // after the stall, a jump is a fault again
    c.tick(&lathe(60_000));
    assert_eq!(c.state(), State::Fault(Fault::EncoderImplausible));
}

#[test]
fn a_small_turn_during_a_stall_is_counted_exactly() {
    let mut c = ctl();
    c.begin_stall();
    c.tick(&lathe(1));
    assert_eq!(c.end_stall(), Stall::Counted);
    c.begin_stall();
    c.tick(&lathe(1));
    assert_eq!(c.end_stall(), Stall::Still);
    assert_eq!(c.state(), State::Idle);
}

#[test]
fn an_index_latched_during_a_stall_becomes_the_new_phase_reference() {
    let mut c = ctl();
    let cpr = c.config().encoder_counts_per_rev as u16;
    // referenced at count 100 before the save (turned there slowly)
    for raw in 1..100 {
        c.tick(&lathe(raw));
    }
    c.tick(&TickInput { lathe: 100, index: Some(100), ..TickInput::default() });
    c.service();
    assert_eq!(c.gear_origin(), 100);
    // the lathe turns ten turns and a bit during the stall: the counter
    // holds its last index crossing (TIM3_CH3 capture), 700 counts back
    c.begin_stall();
    let at = 100u16.wrapping_add(10 * cpr + 900);
    let idx = at.wrapping_sub(700);
    c.tick(&TickInput { lathe: at, index: Some(idx), ..TickInput::default() });
    assert_eq!(c.state(), State::Idle, "not a slip: the count in between is unknown");
    assert_eq!(c.end_stall(), Stall::Lost { reindexed: true });
    assert_eq!(c.gear_origin(), c.status().lathe_counts - 700, "phase re-referenced to the index");
    // the indexes of the next turns are consistent with it
    for raw in 1..2 * cpr {
        let now = at.wrapping_add(raw);
        let index = (now.wrapping_sub(idx) % cpr == 0).then_some(now);
        c.tick(&TickInput { lathe: now, index, ..TickInput::default() });
        assert_eq!(c.state(), State::Idle, "{raw}");
    }
}

#[test]
fn an_upload_with_points_2_pow_23_apart_is_refused_before_it_is_saved() {
    use crate::cam_upload::CamHeader;
    let h = CamHeader { points: 4, period_counts: 2400, counts_per_rev: 2400, max_rate_hz: 10_000, max_accel: 1000 };
    let c = ctl();
    assert_eq!(c.check_cam(&h), Ok(()), "the header alone passes");
    let bad = [0, 1 << 23, 0, 0];
    let e = super::check_table(&h, &bad).unwrap_err().describe();
    assert!(e.contains("2^23"), "{e}");
    // the same table the fit refuses, with the same reason
    let leaked: &'static [i32] = std::boxed::Box::leak(std::boxed::Box::new(bad));
    assert_eq!(super::prepare_cam(&h, leaked, Timing::FIRMWARE).err(), Some(e));
    // a step under 2^23 passes the points' check, and meets the X axis's
    let e = super::check_table(&h, &[0, (1 << 23) - 1, 0, 0]).unwrap_err();
    assert!(matches!(e, crate::cam_upload::TableRefusal::Motion(_)), "{e:?}");
}

#[test]
fn a_phase_nudge_while_synced_is_a_move_not_a_following_error() {
    // `ok phase=10.000` must not be followed by a following-error fault on
    // the next tick with the lathe at rest
    let mut c = ctl();
    c.engage().unwrap();
    for _ in 0..3 {
        c.tick(&TickInput::default());
    }
    assert_eq!(c.state(), State::Synced);
    let nudged = c.config().with("phase", "10").unwrap(); // 89 steps > ferror 64
    c.set_config(nudged).unwrap();
    assert_eq!(c.state(), State::Engaging, "the cutter is moving to the new phase");
    // the step output: each tick's plan goes out two ticks later (`steps::pipe`)
    let (mut emitted, mut pipe) = (0u16, [0u16; 2]);
    for t in 0..5000 {
        let out = c.tick(&TickInput { emitted, ..TickInput::default() });
        emitted = emitted.wrapping_add(pipe[t % 2]);
        pipe[t % 2] = out.plan.count;
        assert!(c.fault().is_none(), "{:?}", c.state());
    }
    assert_eq!(c.state(), State::Synced, "on the new phase");
}

#[test]
fn a_jump_no_lathe_can_make_is_not_taken_as_speed() {
    // during a save's stall, and as a fault: a stopped lathe reads 0 rpm after
    let mut c = ctl();
    c.begin_stall();
    c.tick(&lathe(30_000));
    c.end_stall();
    c.tick(&lathe(30_000));
    assert_eq!(c.status().lathe_velocity_q32, 0);
    assert_eq!(c.engage(), Ok(()), "not refused as too fast");
    let mut c = ctl();
    c.tick(&lathe(1000));
    c.clear();
    c.tick(&lathe(1000));
    assert_eq!(c.status().lathe_velocity_q32, 0);
}

#[test]
fn a_cam_header_is_refused_for_each_limit_alone() {
    use crate::cam_upload::{CamHeader, X_MAX_RATE_HZ};
    let top = X_MAX_RATE_HZ;
    assert_eq!(top, Timing::FIRMWARE.tick_hz / 2, "one X step per two ticks");
    let ok = CamHeader { points: 4, period_counts: 2400, counts_per_rev: 2400, max_rate_hz: top, max_accel: 1 };
    let c = ctl();
    assert_eq!(c.check_cam(&ok), Ok(()));
    let rate = std::format!("cam max-rate must be 1..={top} steps/s (one X step per two ticks), max-accel > 0");
    for bad in
        [CamHeader { max_rate_hz: top + 1, ..ok }, CamHeader { max_rate_hz: 0, ..ok }, CamHeader { max_accel: 0, ..ok }]
    {
        assert_eq!(c.check_cam(&bad), Err(rate.as_str()), "{bad:?}");
    }
    let other = CamHeader { counts_per_rev: 4000, ..ok };
    assert_eq!(c.check_cam(&other), Err("cam table made for another cpr: set cpr or remake the table"));
}

#[test]
fn a_stall_counts_a_tick_s_most_plausible_count_and_loses_one_more_and_each_says_so() {
    for (jump, want) in [(0, Stall::Still), (0, Stall::Counted), (1, Stall::Lost { reindexed: false })] {
        let mut c = ctl();
        let most = c.derived().max_counts_per_tick;
        let at = if want == Stall::Still { 0 } else { most + jump };
        c.begin_stall();
        c.tick(&TickInput { lathe: at as u16, ..TickInput::default() });
        assert_eq!(c.end_stall(), want, "{at} counts in a tick, at most {most}");
    }
    assert_eq!(Stall::Still.describe(), "");
    assert_eq!(Stall::Counted.describe(), " (the lathe turned during the save: counted)");
    assert!(Stall::Lost { reindexed: true }.describe().ends_with("the phase is re-referenced to the index)"));
    assert!(Stall::Lost { reindexed: false }.describe().ends_with("the phase to earlier cuts is lost)"));
}
