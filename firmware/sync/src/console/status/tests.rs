//! The status line field by field (docs/src/first-power-up.md, "Status"): speeds in rpm to a
//! tenth, the phase error in steps to a thousandth, signs included.

use super::*;
use crate::controller::Status;
use crate::state::State;

const TICK_HZ: u32 = crate::Timing::FIRMWARE.tick_hz;

/// One count a tick at the board's 20 kHz on 2400 counts a turn is 500
/// rpm; the cutter driven at 4 steps a tick on 3200 steps a turn is 1500
/// rpm.
fn snapshot(v_q32: i64, phase_error_q16: i64, fault: Option<Fault>) -> Snapshot {
    let state = fault.map_or(State::Synced, State::Fault);
    let cutter = if v_q32 < 0 { -(4 << 16) } else { 4 << 16 };
    let status = Status {
        state,
        lathe_velocity_q32: v_q32,
        phase_error_q16,
        cutter_velocity_q16: if v_q32 == 0 { 0 } else { cutter },
        cutter_steps: -56,
        target_steps: 1234,
        lathe_counts: 99,
        indexed: fault.is_none(),
        index_counts: fault.is_none().then_some(-1),
        divisions: None,
        ticks: 7,
    };
    let config = Config::default().with("max-rpm", "600").unwrap().with("ratio", "11/3").unwrap();
    Snapshot { status, config, tick_hz: TICK_HZ, fault, cam_points: None, shaft_gap: None }
}

fn line(s: &Snapshot) -> std::string::String {
    let mut out = Reply::new();
    s.write(&mut out);
    out.as_str().into()
}

#[test]
fn a_synced_line_shows_every_field() {
    let s = snapshot(1 << 32, -(3 << 16) - (1 << 15), None);
    assert_eq!(
        line(&s),
        "ok state=synced fault=none lathe_rpm=500.0 cutter_rpm=1500.0 phase_err_steps=-3.500 target=1234 cutter=-56 indexed=yes \
         angle_deg=15.0 angle_from=index"
    );
}

#[test]
fn a_lathe_turning_backwards_shows_negative_speeds_and_a_fault_its_reason() {
    let s = snapshot(-(1 << 32), 81_920, Some(Fault::Stall));
    assert_eq!(
        line(&s),
        "ok state=fault fault=stall lathe_rpm=-500.0 cutter_rpm=-1500.0 phase_err_steps=1.250 target=1234 cutter=-56 \
         indexed=no angle_deg=14.9 angle_from=start reason=\"cutter encoder not following: check motor and its encoder\""
    );
}

#[test]
fn the_idle_line_reads_as_the_manual_shows_it() {
    let status = Status {
        state: State::Idle,
        lathe_velocity_q32: 0,
        phase_error_q16: 0,
        cutter_velocity_q16: 0,
        cutter_steps: 0,
        target_steps: 0,
        lathe_counts: 0,
        indexed: false,
        index_counts: None,
        divisions: None,
        ticks: 0,
    };
    let s = Snapshot {
        status,
        config: Config::default(),
        tick_hz: TICK_HZ,
        fault: None,
        cam_points: None,
        shaft_gap: None,
    };
    assert_eq!(
        line(&s),
        "ok state=idle fault=none lathe_rpm=0.0 cutter_rpm=0.0 phase_err_steps=0.000 target=0 cutter=0 indexed=no \
         angle_deg=0.0 angle_from=start"
    );
    // a fitted cam table says so, by its points
    let s = Snapshot { cam_points: Some(250), ..s };
    assert!(line(&s).ends_with(" indexed=no angle_deg=0.0 angle_from=start cam=250"), "{}", line(&s));
}

#[test]
fn under_one_unit_a_negative_value_keeps_its_sign() {
    // 53/65536 count a tick backwards: −0.404 rpm at 20 kHz, shown −0.4;
    // the cutter at 1/256 step a tick backwards, −1.46 rpm: −1.4 (tenths,
    // toward 0); −0.25 step
    let mut s = snapshot(-53 << 16, -(1 << 14), None);
    s.status.cutter_velocity_q16 = -256;
    let l = line(&s);
    assert!(l.contains(" lathe_rpm=-0.4 cutter_rpm=-1.4 phase_err_steps=-0.250 "), "{l}");
}

#[test]
fn a_phase_error_beyond_2_pow_30_steps_is_shown_clamped() {
    let l = line(&snapshot(0, i64::MAX, None));
    assert!(l.contains(" phase_err_steps=1073741824.000 "), "{l}");
    let l = line(&snapshot(0, i64::MIN, None));
    assert!(l.contains(" phase_err_steps=-1073741824.000 "), "{l}");
}

#[test]
fn thousandths_and_tenths_print_their_digits() {
    let show = |v: i64| std::format!("{} {}", Milli(v), Tenths(v));
    assert_eq!(show(0), "0.000 0.0");
    assert_eq!(show(7), "0.007 0.7");
    assert_eq!(show(-1_234), "-1.234 -123.4");
    assert_eq!(std::format!("{}", Milli::steps_q16(3 << 16)), "3.000");
}

#[test]
fn a_fresh_controllers_status_line_is_the_idle_line() {
    let c = crate::controller::Controller::new(Config::default(), crate::timing::Timing::FIRMWARE);
    let mut out = Reply::new();
    write_status(&c, &mut out);
    assert_eq!(
        out.as_str(),
        "ok state=idle fault=none lathe_rpm=0.0 cutter_rpm=0.0 phase_err_steps=0.000 target=0 cutter=0 indexed=no \
         angle_deg=0.0 angle_from=start"
    );
}

#[test]
fn the_cutter_speed_is_the_speed_it_is_driven_at_not_the_lathes_times_the_ratio() {
    // idle with the lathe turning: the cutter stands
    let mut s = snapshot(1 << 32, 0, None);
    s.status.state = State::Idle;
    s.status.cutter_velocity_q16 = 0;
    assert!(line(&s).contains(" lathe_rpm=500.0 cutter_rpm=0.0 "), "{}", line(&s));
    // with dir=opposite the motor's steps count down while the lathe's count up
    s.status.cutter_velocity_q16 = -(4 << 16);
    assert!(line(&s).contains(" lathe_rpm=500.0 cutter_rpm=-1500.0 "), "{}", line(&s));
}

#[test]
fn a_controller_turning_the_lathe_while_idle_reports_its_cutter_still() {
    use crate::controller::{Controller, TickInput};
    let mut c = Controller::new(Config::default(), crate::timing::Timing::FIRMWARE);
    c.start(0, 0, 0);
    for k in 1..=2_000u32 {
        c.tick(&TickInput { lathe: k as u16, ..TickInput::default() });
    }
    let mut out = Reply::new();
    write_status(&c, &mut out);
    let l = out.as_str();
    assert!(l.contains(" cutter_rpm=0.0 ") && !l.contains(" lathe_rpm=0.0 "), "{l}");
}

/// Every field at its widest (the speeds at their bounds, the positions
/// at i64's, the longest reason, a cam, a cutter encoder, dividing on the
/// finest encoder): the line fits a reply, whole.
#[test]
fn the_longest_status_line_fits_a_reply() {
    let mut longest = 0;
    for (divisions, counts) in [(1, 499_999), (1, 500_001), (7, 71_429), (3600, 999_861), (3600, 999_999)] {
        let status = Status {
            state: State::Fault(Fault::LostSteps),
            lathe_velocity_q32: -(16_000 << 32),
            phase_error_q16: i64::MIN,
            cutter_velocity_q16: -(1 << 20),
            cutter_steps: i64::MIN,
            target_steps: i64::MIN,
            lathe_counts: counts - 1_000_000_000,
            indexed: true,
            index_counts: Some(-999_999),
            divisions: Some(divisions),
            ticks: u64::MAX,
        };
        let config = Config { encoder_counts_per_rev: 1_000_000, ..Config::default() };
        let s = Snapshot {
            status,
            config,
            tick_hz: TICK_HZ,
            fault: Some(Fault::LostSteps),
            cam_points: Some(1024),
            shaft_gap: Some(crate::controller::ShaftGap { diff: i64::MIN, cpr: 1 }),
        };
        let l = line(&s);
        assert!(l.ends_with(&std::format!("reason=\"{}\"", Fault::LostSteps.reason())), "cut: {l}");
        assert!(l.contains(&std::format!(" divide={divisions} ")), "{l}");
        longest = longest.max(l.len());
    }
    assert!(longest < crate::console::REPLY_LEN, "{longest}");
}
