//! Scenarios: the real core cuts what the geometry predicts.

use polyturn_host::geometry::Direction;
use polyturn_host::sim::{Event, Scenario, Start};
use polyturn_scenarios::*;
use polyturn_sync::DriveKind;

#[test]
fn hexagon_at_constant_speed_holds_a_step_and_five_microns() {
    let r = simulate(&scenario(hexagon(), 600.0, 10.0, 0.0, Start::Rest, DriveKind::Stepper));
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    assert!(r.max_error_steps_cutting <= 1.0, "error while cutting {}", r.max_error_steps_cutting);
    assert!(r.max_profile_deviation <= 0.005, "section off by {} mm", r.max_profile_deviation);
    assert_eq!(r.final_error_steps, 0);
    let s = r.section.summary();
    assert_eq!(s.sides, 6);
    assert!((s.across_flats.unwrap() - 17.0).abs() < 0.002);
}

#[test]
fn fractional_eleven_thirds_with_ripple_engaged_while_spinning_never_drifts() {
    let setup = setup("11/3", 3, Direction::Same, 2.0);
    let r = simulate(&scenario(setup, 300.0, 20.0, 0.05, Start::Spinning, DriveKind::Stepper));
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    assert_eq!(r.final_error_steps, 0, "drift");
    assert!(r.max_profile_deviation <= 0.010, "section off by {} mm", r.max_profile_deviation);
    // Issue target is 2 steps; sampling the encoder at the tick rate aliases
    // when the count rate crosses half the tick rate (see README): 3 steps.
    assert!(r.max_error_steps_cutting <= 3.0, "error while cutting {}", r.max_error_steps_cutting);
    assert_eq!(r.section.summary().sides, 11);
}

#[test]
fn engaging_again_while_spinning_lands_on_the_first_passes_flats() {
    let mut sc = scripted(hexagon(), Start::Spinning, 1200.0, &[(400.0, 4.0), (0.0, 0.2)]);
    sc.events = vec![Event::Engage(0.2), Event::Disengage(1.5), Event::Engage(2.4)];
    let r = simulate(&sc);
    assert_eq!(r.passes.len(), 2, "two engagements");
    let gap = section_gap(&r.passes[0], &r.passes[1]);
    assert!(gap < 0.005, "second pass misses the first's flats by {gap} mm");
    assert_eq!(r.final_error_steps, 0);
}

#[test]
fn the_lathe_reverses_and_comes_back_to_the_same_phase() {
    let sc = scripted(hexagon(), Start::Rest, 600.0, &[(300.0, 1.0), (-300.0, 1.0), (0.0, 0.2)]);
    let r = simulate(&sc);
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    assert_eq!(r.final_error_steps, 0);
    assert!(r.encoder_counts.abs() < 2400 * 2, "came back near the start: {}", r.encoder_counts);
    assert!(r.max_profile_deviation < 0.006, "{}", r.max_profile_deviation);
}

#[test]
fn a_load_dip_in_lathe_speed_is_followed_without_fault() {
    let mut sc = scenario(hexagon(), 600.0, 15.0, 0.02, Start::Spinning, DriveKind::Stepper);
    sc.lathe.dips = vec![(1.0, 0.3, 0.15)];
    let r = simulate(&sc);
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    assert!(r.max_profile_deviation < 0.006, "{}", r.max_profile_deviation);
}

#[test]
fn a_deliberately_truncating_ratio_is_caught_by_the_section_check() {
    // The check must be able to fail: a core whose ratio is 3/1 instead of 2/1.
    let mut sc = scenario(hexagon(), 300.0, 5.0, 0.0, Start::Spinning, DriveKind::Stepper);
    sc.sabotage_ratio_num = 1;
    let r = simulate(&sc);
    assert!(r.max_profile_deviation > 0.1, "broken core not caught: {}", r.max_profile_deviation);
}

fn x_run(rpm: f64, steps_per_mm: f64, max_rate_hz: f64) -> polyturn_host::sim::SimResult {
    // a hardware-timed X output, which the board has not got: idealised
    x_run_on(rpm, steps_per_mm, max_rate_hz, polyturn_host::sim::XOutput::Timed)
}

fn x_run_on(
    rpm: f64,
    steps_per_mm: f64,
    max_rate_hz: f64,
    output: polyturn_host::sim::XOutput,
) -> polyturn_host::sim::SimResult {
    use polyturn_host::compensate;
    use polyturn_host::sim::XSim;
    let s = setup("3", 2, Direction::Same, 2.0);
    let plan = compensate::plan(&s, rpm, 1e4, 1e6);
    assert_eq!(plan.limited_by, None);
    let (table, period_counts) = compensate::cam_table(&s, &plan, 2400, steps_per_mm, 1024);
    let mut sc = scenario(s, rpm, 4.0, 0.0, Start::Spinning, DriveKind::Stepper);
    sc.x_axis = Some(XSim {
        table: Vec::leak(table),
        period_counts,
        steps_per_mm,
        max_rate_hz,
        max_accel: 1e8,
        output,
        backlash_steps: 0.0,
    });
    simulate(&sc)
}

#[test]
fn an_x_axis_on_the_compensation_cam_cuts_straight_flats() {
    // 3:1 × 2 edges: the fixed axis leaves the flats 62 µm hollow.
    let fixed = polyturn_host::geometry::Section::ideal(&setup("3", 2, Direction::Same, 2.0), 1024).summary();
    assert!(fixed.flat_deviation < -0.05, "{fixed:?}");
    // 1600 steps/mm: a 200-step motor at 1/16 on a 2 mm lead screw.
    let r = x_run(100.0, 1600.0, 200_000.0);
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    let after = r.section.summary();
    eprintln!("the compensated flats {:.1} um from straight", after.flat_deviation * 1e3);
    // Measured 2.7 µm with this 10^8 steps/s² axis (2.4 µm with a very stiff
    // one, 10^12): the linear table's kinks cost an acceleration-limited follower a
    // few ticks each, and the cutter's own phase error (≈ 0.6 step) moves the
    // tip along the steep part of the X profile. Goal 2 µm: not yet (README).
    assert!(after.flat_deviation.abs() < 0.010, "flats {} mm from straight", after.flat_deviation);
    assert!((after.inscribed_radius - 8.0).abs() < 0.002, "{after:?}");
    assert_eq!(r.final_error_steps, 0);
}

#[test]
fn an_x_axis_that_cannot_keep_up_trips_the_following_error() {
    // 16 000 steps/mm needs 700 k steps/s of X at 100 rpm: more than the
    // step generator emits. The core must notice, not cut a wrong section.
    let r = x_run(100.0, 16_000.0, 1e7);
    assert!(r.faults.iter().any(|(_, f)| *f == polyturn_sync::Fault::FollowingError), "{:?}", r.faults);
}

#[test]
fn the_board_x_pins_cannot_follow_what_a_timed_output_follows() {
    // 100 rpm at 1600 steps/mm asks ~19 000 X steps/s: a timed output
    // keeps up (above), the board's pins (one step per two ticks) cannot,
    // and the core says so rather than cut a wrong section.
    let r = x_run_on(100.0, 1600.0, 200_000.0, polyturn_host::sim::XOutput::Gpio);
    assert!(r.faults.iter().any(|(_, f)| *f == polyturn_sync::Fault::FollowingError), "{:?}", r.faults);
}

/// What `polyturn compensate --table` writes for the board's X axis (800
/// steps/mm, its 10 000 steps/s), read back as `device upload-cam` reads
/// it, run by the core at the lathe speed the planner allows.
/// The lathe's speed wanders 2 % once a turn, as a real one's does.
fn board_table_run(rpm: f64, axis: (f64, f64), backlash_steps: f64) -> (polyturn_host::sim::SimResult, String) {
    board_table_run_on(rpm, axis, backlash_steps, (3200, 0.02))
}

/// The same with a cutter motor of `cutter_steps` a turn and a lathe
/// whose speed wanders by `ripple`.
fn board_table_run_on(
    rpm: f64,
    (speed, accel): (f64, f64),
    backlash_steps: f64,
    (cutter_steps, ripple): (u32, f64),
) -> (polyturn_host::sim::SimResult, String) {
    use polyturn_host::cli::{console_line::cam_table, dispatch};
    use polyturn_host::sim::XSim;
    let file = std::env::temp_dir().join(format!("polyturn-compensate-{}.json", std::process::id()));
    let line = format!(
        "compensate --cutter-radius 50 --stock-radius 10 --depth 2 --ratio 3 --edges 2 --direction same --rpm {rpm} --x-max-speed {speed} --x-max-accel {accel} --table {}",
        file.display()
    );
    let argv: Vec<String> = line.split(' ').map(String::from).collect();
    let report = dispatch(&argv).expect("compensate writes its table");
    let t = cam_table("table", &std::fs::read_to_string(&file).unwrap()).expect("upload-cam takes it");
    let _ = std::fs::remove_file(&file);
    let s = setup("3", 2, Direction::Same, 2.0);
    let mut sc = Scenario::standard(s, rpm, 3.0, ripple, Start::Spinning, 2400, cutter_steps, DriveKind::Stepper, 7);
    sc.x_axis = Some(XSim {
        table: Vec::leak(t.points),
        period_counts: t.period_counts,
        steps_per_mm: t.steps_per_mm,
        max_rate_hz: t.max_rate_hz as f64,
        max_accel: t.max_accel as f64,
        output: polyturn_host::sim::XOutput::Gpio,
        backlash_steps,
    });
    (simulate(&sc), report)
}

#[test]
fn the_table_compensate_writes_cuts_straight_flats_at_the_board_x_rate() {
    // The board's X axis (one step per two ticks, 12.5 mm/s at 800
    // steps/mm) follows this 3:1 x 2 up to 28.7 rpm, the planner says
    // (3.3 µm measured, with the lathe's 2 % ripple).
    let (r, report) = board_table_run(25.0, (12.5, 5000.0), 0.0);
    assert!(report.contains("allows up to 28.7 rpm"), "{report}");
    assert!(r.faults.is_empty(), "{:?}", r.faults);
    let after = r.section.summary();
    eprintln!("the board's table: flats {:.1} um from straight at 25 rpm", after.flat_deviation * 1e3);
    assert!(after.flat_deviation.abs() < 0.004, "flats {} mm from straight", after.flat_deviation);
    assert!((after.inscribed_radius - 8.0).abs() < 0.003, "{after:?}");
    assert_eq!(r.final_error_steps, 0);
}

/// A hobby cross-slide: a Sherline lathe's X as LinuxCNC's sample
/// configuration and grbl's defaults set it, 800 steps/mm (a 0.050"
/// screw), 8 mm/s and 50 mm/s² (sources in docs/src/noncircular.md).
const HOBBY: (f64, f64) = (8.0, 50.0);

#[test]
fn a_hobby_cross_slide_straightens_the_flats_to_5_um_at_5_rpm_if_its_backlash_is_kept_taken_up() {
    let run = |rpm: f64, play_mm: f64, (cutter_steps, ripple): (u32, f64)| {
        let (r, report) = board_table_run_on(rpm, HOBBY, play_mm * 800.0, (cutter_steps, ripple));
        assert!(report.contains("allows up to 5.6 rpm"), "{report}");
        assert!(r.faults.is_empty(), "{:?}", r.faults);
        let flats = r.section.summary().flat_deviation;
        eprintln!(
            "hobby slide at {rpm} rpm, {:.0} um of play, cutter {cutter_steps} steps/turn, ripple {ripple}: flats {:.1} um from straight",
            play_mm * 1e3,
            flats * 1e3
        );
        flats.abs()
    };
    // The planner allows 5.6 rpm (its 50 mm/s²). At 5 rpm, with the
    // lathe's 2 % ripple, the flats come within 5 µm.
    let tight = run(5.0, 0.0, (3200, 0.02));
    assert!(tight < 0.0055, "{tight}");
    // On a steady lathe what is left is the cutter's step (a 50 mm tip
    // moves 98 µm a step of 3200), which the slow rotor takes whole: with
    // 12 800 (a 200-step motor at 1/64) the flats come within the 2 µm goal.
    assert!(run(5.0, 0.0, (3200, 0.0)) > 0.003);
    assert!(run(5.0, 0.0, (12_800, 0.0)) < 0.002);
    // Nearer the limit the follower, held to 50 mm/s², lags.
    assert!(run(5.5, 0.0, (3200, 0.02)) > 2.0 * tight);
    // 40 µm of play (an adjusted nut) that nothing keeps taken up: X
    // reverses at every flat's middle, and the slide waits out the play
    // there; most of the 62 µm correction is lost.
    assert!(run(5.0, 0.040, (3200, 0.02)) > 0.030);
}
