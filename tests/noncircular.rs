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
    let polygon = Polygon { sides: 8, apothem_mm: 20.0 };
    let axis = Axis { rpm: 12.0, max_speed: 12.0, max_accel: 2000.0 };
    let Outcome::Sharp(path, _) = plan(polygon, 3, axis) else { panic!("sharp corners fit at 12 rpm") };
    let mut table = build(&path, cpr, 800.0, (9_600, 1_600_000));
    table.period_counts = (table.period_counts as i32 + sabotage_period) as u32;
    let sc = SinglePoint { table, apothem_mm: 20.0, rpm, ripple, revolutions: 4.0, seed: 3, output: XOutput::Gpio };
    let r = run(&sc, &path).expect("runs");
    assert!(r.synced_ticks > 0, "never synchronised");
    eprintln!("{cpr} counts, {rpm} rpm, period {sabotage_period:+}: {:.2} um from the octagon", r.max_deviation * 1e3);
    (r.max_deviation, r.faults)
}

#[test]
fn an_octagon_turned_by_a_single_point_tool_on_the_cam_has_sharp_corners_within_microns() {
    // 2400 counts/rev: at the corners X moves 23 µm per lathe count, and
    // the sub-count estimate leaves a few µm (2.7 measured)
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
