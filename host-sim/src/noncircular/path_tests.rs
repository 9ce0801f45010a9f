//! The smooth paths against the noncircular turning note's claims: the minimum over the
//! revolutions is the polygon, velocity is continuous at every junction,
//! the sides are cut in Theorem 2's order; and the fallback's fillets.

use super::path::{Path, Polygon, ToolPath};
use super::plan::{best_link, evaluate, plan, Axis, Outcome, TOLERANCE_MM};
use super::rounded::Rounded;
use super::table::build;
use super::{order, smallest_m};
use std::f64::consts::TAU;

const SLOW: Axis = Axis { rpm: 5.0, max_speed: 100.0, max_accel: 5000.0 };

fn sharp(n: u32, r: f64) -> (Path, super::plan::Evaluation) {
    best_link(Polygon { sides: n, apothem_mm: r }, smallest_m(n).unwrap(), SLOW)
}

/// Tracking the polygon directly (the noncircular turning note, Fig. 3): the velocity steps
/// at every corner. A path the continuity check must reject.
struct Direct(Polygon);

impl ToolPath for Direct {
    fn polygon(&self) -> Polygon {
        self.0
    }
    fn revolutions(&self) -> u32 {
        1
    }
    fn period(&self) -> f64 {
        TAU / self.0.sides as f64
    }
    fn at(&self, phi: f64) -> [f64; 3] {
        [self.0.radius(phi), 0.0, 0.0]
    }
    fn junctions(&self) -> Vec<f64> {
        (0..self.0.sides).map(|k| (k as f64 + 0.5) * self.period()).collect()
    }
}

#[test]
fn the_minimum_over_the_revolutions_is_the_polygon_within_a_micron() {
    for n in 3..=12 {
        let (_, e) = sharp(n, 20.0);
        assert!(e.excess < TOLERANCE_MM && e.overcut < TOLERANCE_MM, "N = {n}: {e:?}");
    }
}

#[test]
fn velocity_is_continuous_at_every_cut_and_link_junction() {
    for n in [5, 6, 7, 8, 12] {
        let (p, e) = sharp(n, 20.0);
        assert_eq!(p.junctions().len(), 2 * n as usize);
        assert!(e.velocity_jump < 1e-4 * e.peak_speed, "N = {n}: jump {} of {}", e.velocity_jump, e.peak_speed);
    }
    // the check itself: tracking the sharp polygon directly is caught
    let direct = evaluate(&Direct(Polygon { sides: 8, apothem_mm: 20.0 }), SLOW);
    assert!(direct.velocity_jump > 0.1 * sharp(8, 20.0).1.peak_speed, "{direct:?}");
}

#[test]
fn the_sides_are_cut_in_theorem_2_order() {
    for n in [5, 7, 8, 12] {
        let (p, _) = sharp(n, 20.0);
        let m = smallest_m(n).unwrap();
        let mut seen: Vec<u32> = Vec::new();
        let samples = 512 * n * m;
        for k in 0..samples {
            let phi = TAU * m as f64 * (k as f64 + 0.5) / samples as f64;
            // the side under the tool, from the workpiece angle
            let side = ((phi / TAU * n as f64 + 0.5).floor() as u32) % n;
            if p.cutting(phi) && seen.last() != Some(&side) {
                seen.push(side);
            }
        }
        // the last samples are already the first cut of the next round
        assert_eq!(seen.last(), Some(&0));
        assert_eq!(seen[..n as usize], order(n, m), "N = {n}");
    }
}

#[test]
fn the_cam_table_as_the_core_interpolates_it_stays_within_a_micron() {
    let (p, _) = sharp(8, 20.0);
    let table = build(&p, 2400, 800.0, (9_600, 1_600_000));
    assert_eq!(table.period_counts, 900, "3/8 of a revolution");
    let dev = table.deviation(&p, 8192);
    assert!(dev < TOLERANCE_MM, "{dev}");
    // a coarse axis is reported, not hidden: 10 µm steps leave ~5 µm
    assert!(build(&p, 2400, 100.0, (1, 1)).deviation(&p, 8192) > 2e-3);
}

#[test]
fn a_fillet_cuts_the_corner_back_by_the_formula_and_leaves_the_flats() {
    let poly = Polygon { sides: 6, apothem_mm: 15.0 };
    let f = Rounded { polygon: poly, radius_mm: 2.0 };
    // sharp corner R/cos30°; the fillet's apex is ρ/cos30° − ρ inside it
    let expected = 2.0 / (TAU / 12.0).cos() - 2.0;
    assert!((f.shortfall() - expected).abs() < 1e-9);
    assert!((poly.radius(TAU / 12.0) - f.section(TAU / 12.0) - expected).abs() < 1e-6);
    for k in 0..600 {
        let phi = TAU * k as f64 / 600.0;
        let (cut, ideal) = (f.section(phi), poly.radius(phi));
        assert!(cut <= ideal + 1e-9, "a fillet never leaves material outside the polygon");
        if poly.side_angle(phi).abs() < f.tangent() {
            assert!((cut - ideal).abs() < 1e-9, "the flat is untouched at {phi}");
        }
    }
}

#[test]
fn too_fast_for_sharp_corners_gives_the_smallest_fillet_that_fits() {
    let poly = Polygon { sides: 8, apothem_mm: 20.0 };
    let axis = Axis { rpm: 12.0, max_speed: 12.0, max_accel: 2000.0 };
    assert!(matches!(plan(poly, 3, axis), Outcome::Sharp(..)));
    let mut last = 0.0;
    for rpm in [20.0, 30.0, 45.0] {
        let Outcome::Rounded(f, e, _) = plan(poly, 3, Axis { rpm, ..axis }) else { panic!("{rpm} rpm") };
        assert!(e.max_rpm >= rpm && e.peak_speed <= axis.max_speed * 1.0001, "{rpm}: {e:?}");
        // a slightly smaller fillet would not fit
        let tighter = Rounded { radius_mm: f.radius_mm * 0.98, ..f };
        assert!(evaluate(&tighter, Axis { rpm, ..axis }).max_rpm < rpm);
        assert!(f.radius_mm > last, "faster needs a larger fillet");
        last = f.radius_mm;
    }
}

#[test]
fn the_upload_lines_deliver_the_table_to_the_core_intact() {
    let (p, _) = sharp(8, 20.0);
    let table = build(&p, 2400, 800.0, (9_600, 1_600_000));
    let mut up = Box::new(polyturn_sync::cam_upload::CamUpload::default());
    for line in table.upload_lines(88) {
        assert!(line.len() <= 88, "fits the console's line buffer: {line}");
        up.line(line.strip_prefix("cam").unwrap()).unwrap();
    }
    let (h, points) = up.table().expect("complete and checked");
    assert_eq!((h.period_counts, points), (900, &table.points[..]));
}

/// Values of ten digits and a sign do not fit eight to a line: the lines
/// take fewer, each within the length given, and the table arrives intact.
#[test]
fn long_values_go_fewer_to_a_line_and_arrive_intact() {
    let (p, _) = sharp(8, 20.0);
    let mut table = build(&p, 2400, 800.0, (9_600, 1_600_000));
    table.points.iter_mut().for_each(|v| *v = -2_000_000_000);
    let lines = table.upload_lines(88);
    let mut up = Box::new(polyturn_sync::cam_upload::CamUpload::default());
    for line in &lines {
        assert!(line.len() <= 88, "{} > 88: {line}", line.len());
        up.line(line.strip_prefix("cam").unwrap()).unwrap();
    }
    assert!(lines.len() > 2 + table.points.len() / 8, "fewer than 8 values a line");
    let (_, points) = up.table().expect("complete and checked");
    assert_eq!(points, &table.points[..]);
}
