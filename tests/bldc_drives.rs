//! The BLDC path on the drive the firmware really feeds (issue 30): an RC
//! servo pulse, 50 Hz, in whole µs (`polyturn_firmware::esc`), to a hobby
//! ESC with no speed loop, its speed sagging under the cutting load. The
//! phase loop (`polyturn_sync::drive`) was tuned on a drive that takes
//! every tick's command; held for a whole frame its gains are far too
//! high, and the cutter loses phase. These tests pin that finding, against
//! the idealised drive the simulator used before, until the phase loop's
//! gains come from the drive's update rate (issue 30, part 2).

use polyturn_host::sim::bldc::BldcDrive;
use polyturn_host::sim::{SimResult, Start};
use polyturn_scenarios::*;
use polyturn_sync::{DriveKind, Fault};

/// The hexagon at 600 rpm, 2 % ripple, engaged at 0.2 s while spinning.
fn hexagon_on(drive: BldcDrive) -> SimResult {
    let mut sc = scenario(hexagon(), 600.0, 10.0, 0.02, Start::Spinning, DriveKind::Bldc);
    sc.bldc_drive = drive;
    simulate(&sc)
}

/// Seconds from engaging to the first following-error fault, if any.
fn lost_after_s(r: &SimResult) -> Option<f64> {
    r.faults.iter().find(|f| f.1 == Fault::FollowingError).map(|f| f.0 as f64 / 25_000.0 - 0.2)
}

#[test]
fn through_a_50_hz_rc_esc_the_bldc_loses_phase_within_a_second() {
    let r = hexagon_on(BldcDrive::FIRMWARE);
    let t = lost_after_s(&r).unwrap_or_else(|| panic!("held phase: {:?}, {:.2} counts", r.faults, r.max_error_steps));
    assert!(t < 1.0, "{t:.2} s");
    eprintln!("rc esc 50 Hz: following error {t:.2} s after engaging");
}

#[test]
fn faster_or_speed_controlled_drives_lose_it_too_with_todays_gains() {
    for (name, d) in [
        ("rc esc 400 Hz", BldcDrive::RcEsc { frame_hz: 400.0 }),
        ("speed loop 50 Hz", BldcDrive::SpeedLoop { frame_hz: 50.0, tau: 2e-3 }),
        ("speed loop 1 kHz", BldcDrive::SpeedLoop { frame_hz: 1000.0, tau: 2e-3 }),
    ] {
        let r = hexagon_on(d);
        let t = lost_after_s(&r).unwrap_or_else(|| panic!("{name} held phase: {:.2} counts", r.max_error_steps));
        eprintln!("{name}: following error {t:.2} s after engaging");
    }
}

#[test]
fn on_the_idealised_drive_it_stays_within_its_phase_window() {
    let r = hexagon_on(BldcDrive::Ideal);
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    assert!(r.max_error_steps_cutting < 16.0, "{} counts", r.max_error_steps_cutting);
    assert!(r.max_profile_deviation < 0.05, "{}", r.max_profile_deviation);
    eprintln!(
        "ideal: {:.2} counts while cutting, section {:.1} µm from the ideal",
        r.max_error_steps_cutting,
        r.max_profile_deviation * 1e3
    );
}

#[test]
fn the_guided_setup_warns_when_the_drive_is_bldc() {
    use polyturn_host::cli::setup_plan::{summary, BLDC_WARNING};
    let bldc = polyturn_sync::Config::default().with("drive", "bldc").unwrap();
    assert!(summary(&bldc, &[]).ends_with(BLDC_WARNING));
    assert!(!summary(&polyturn_sync::Config::default(), &[]).contains("warning"));
}
