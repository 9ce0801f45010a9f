//! Noncircular turning end to end (the noncircular turning note,
//! "Noncircular Turning of Workpieces With Sharp Corners"): the real core runs the cam
//! table `polyturn cam` makes, a single-point tool on the X axis, and the
//! section it cuts is compared with the ideal octagon.

use polyturn_host::noncircular::path::Polygon;
use polyturn_host::noncircular::plan::{plan, Axis, Outcome};
use polyturn_host::noncircular::table::build;
use polyturn_host::sim::single_point::{run, SinglePoint};
use polyturn_host::sim::XOutput;

fn octagon(cpr: u32, rpm: f64, ripple: f64, sabotage_period: i32) -> (f64, Vec<polyturn_sync::Fault>) {
    octagon_on(Axis { rpm: 12.0, max_speed: 12.0, max_accel: 2000.0 }, cpr, rpm, ripple, sabotage_period)
}

/// The octagon planned for `axis` (mm/s, mm/s² at 800 steps/mm), cut at `rpm`.
fn octagon_on(axis: Axis, cpr: u32, rpm: f64, ripple: f64, sabotage_period: i32) -> (f64, Vec<polyturn_sync::Fault>) {
    let polygon = Polygon { sides: 8, apothem_mm: 20.0 };
    let Outcome::Sharp(path, _) = plan(polygon, 3, axis) else { panic!("sharp corners fit at {} rpm", axis.rpm) };
    let rates = ((axis.max_speed * 800.0) as u32, (axis.max_accel * 800.0) as u32);
    let mut table = build(&path, cpr, 800.0, rates);
    table.period_counts = (table.period_counts as i32 + sabotage_period) as u32;
    let sc = SinglePoint {
        table,
        apothem_mm: 20.0,
        rpm,
        ripple,
        revolutions: 4.0,
        seed: 3,
        output: XOutput::Gpio,
        backlash_steps: 0.0,
    };
    let r = run(&sc, &path).expect("runs");
    assert!(r.synced_ticks > 0, "never synchronised");
    eprintln!("{cpr} counts, {rpm} rpm, period {sabotage_period:+}: {:.2} um from the octagon", r.max_deviation * 1e3);
    (r.max_deviation, r.faults)
}

#[test]
fn an_octagon_turned_by_a_single_point_tool_on_the_cam_has_sharp_corners_within_microns() {
    // 2400 counts/rev: at the corners X moves 23 µm per lathe count, and
    // the sub-count estimate leaves a few µm (2.6 measured)
    let (dev, faults) = octagon(2400, 12.0, 0.02, 0);
    assert!(faults.is_empty(), "{faults:?}");
    assert!(dev < 5e-3, "section {:.2} um from the octagon", dev * 1e3);
}

#[test]
fn a_finer_lathe_encoder_brings_the_octagon_within_two_microns_even_slowly() {
    let (dev, faults) = octagon(8000, 6.0, 0.02, 0);
    assert!(faults.is_empty(), "{faults:?}");
    assert!(dev < 2.5e-3, "section {:.2} um from the octagon", dev * 1e3);
}

#[test]
fn a_cam_table_whose_period_is_one_count_off_is_caught_by_the_section_check() {
    let (dev, _) = octagon(2400, 12.0, 0.0, 1);
    assert!(dev > 20e-3, "a drifting cam must show: {:.2} um", dev * 1e3);
}

/// A hobby cross-slide: a Sherline lathe's X as LinuxCNC's sample
/// configuration and grbl's defaults set it, 8 mm/s and 50 mm/s²
/// (docs/src/noncircular.md); the corners hold the plan to 8.5 rpm.
const HOBBY: Axis = Axis { rpm: 8.0, max_speed: 8.0, max_accel: 50.0 };

#[test]
fn a_hobby_cross_slide_does_not_yet_follow_the_octagon_the_planner_allows_and_the_core_says_so() {
    // A known limit, measured: the core holds X to the axis's 50 mm/s² on
    // every tick's change of velocity (10^-4 steps per tick²), and the
    // lathe's speed estimate and the table's whole-step bends change it
    // by more, so the X command falls behind its cam: by more than ferror
    // at 8 rpm, a following error, not a wrong section. When the core
    // smooths the cam's velocity this fails: update the book.
    let (_, faults) = octagon_on(HOBBY, 2400, 8.0, 0.02, 0);
    assert_eq!(faults, [polyturn_sync::Fault::FollowingError]);
    // slower and with a finer encoder it cuts, 16 µm from the octagon
    let (dev, faults) = octagon_on(HOBBY, 8000, 4.0, 0.02, 0);
    eprintln!("hobby slide, 8000 counts, 4 rpm: {:.1} um from the octagon", dev * 1e3);
    assert!(faults.is_empty(), "{faults:?}");
    assert!(dev > 0.005 && dev < 0.05, "{dev}");
}
