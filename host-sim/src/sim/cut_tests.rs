//! The recorder against the model: a perfect cutter must cut the ideal section.
use super::CutRecorder;
use crate::geometry::{Direction, Section, Setup};
use polyturn_sync::Ratio;
use std::f64::consts::TAU;

fn perfect_cut(setup: &Setup, rpm: f64, tick_hz: f64, revs: f64) -> f64 {
    let bins = 512;
    let mut rec = CutRecorder::new(setup, bins);
    let da = rpm / 60.0 * TAU / tick_hz;
    let s = setup.direction.sign();
    let mut a = 0.0;
    while a < revs * TAU {
        rec.record(a, s * setup.gr() * a, 0.0);
        a += da;
    }
    let (cut, ideal) = (rec.section(), Section::ideal(setup, bins));
    cut.envelope.radius.iter().zip(&ideal.envelope.radius).map(|(c, i)| (c - i).abs()).fold(0.0, f64::max)
}

#[test]
fn a_perfect_cutter_cuts_the_ideal_section_at_any_speed() {
    for (ratio, edges, dir) in [
        ("2", 3, Direction::Same),
        ("11/3", 3, Direction::Same),
        ("3", 2, Direction::Opposite),
        ("11/3", 1, Direction::Same),
    ] {
        let setup = Setup {
            cutter_radius_mm: 50.0,
            stock_radius_mm: 10.0,
            depth_mm: 1.5,
            ratio: Ratio::parse(ratio).unwrap(),
            edges,
            direction: dir,
        };
        let revs = setup.pattern().1 as f64 + 0.5;
        for rpm in [60.0, 600.0, 1000.0, 2000.0] {
            let dev = perfect_cut(&setup, rpm, polyturn_sync::Timing::FIRMWARE.tick_hz as f64, revs);
            assert!(dev < 1e-3, "{ratio} x {edges} {dir:?} at {rpm} rpm: {dev} mm");
        }
    }
}
