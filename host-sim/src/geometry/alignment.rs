//! What a cutter spindle set up slightly wrong does to the section: the book's
//! spindle chapter (`docs/src/spindle.md`) takes its tables from here.
//!
//! Centre height. Put the cutter's axis `h` above the lathe's centre line, at
//! (X0, h) instead of (X0, 0). Seen from the work the tip is then
//! e^{−ia}·((X0 + ih) − R1·e^{iθ}) (the module's P(a) with X0 → X0 + ih). With
//! X0 + ih = D·e^{iβ}, D = √(X0² + h²), β = atan2(h, X0), and the cutter's phase
//! counted from the tilted line of centres (θ = β + θ'), that is
//! e^{iβ}·e^{−ia}·(D − R1·e^{iθ'}): the ideal pass at centre distance D, turned
//! by β. So a height error cuts the same polygon, shallower by D − X0 ≈ h²/2X0
//! and turned by β (which the phase setting absorbs): second order, where a
//! single-point tool's height error is first order.
//!
//! Parallelism. The axes tilted toward the work by an angle α change X0 by
//! z·tan α at a distance z along the work: a taper, first order. Tilted in the
//! vertical plane they change the height instead: second order, as above.

use super::{Section, Setup};

/// The setup that cuts what `s` cuts with the cutter's axis `height_mm` off the
/// lathe's centre line, and the angle (rad) its section is turned by.
pub fn with_centre_height(s: &Setup, height_mm: f64) -> (Setup, f64) {
    let x0 = s.centre_distance();
    let d = x0.hypot(height_mm);
    (Setup { depth_mm: s.depth_mm - (d - x0), ..*s }, height_mm.atan2(x0))
}

/// The smallest diameter of the section (across flats for an even N; twice
/// the inscribed radius for any N), mm.
pub fn smallest_diameter(s: &Setup) -> f64 {
    2.0 * summary(s).inscribed_radius
}

/// The book's two setups: the demo's hexagon and the 11-sided part.
fn setups() -> [(&'static str, Setup); 2] {
    use super::Direction::Same;
    use polyturn_sync::Ratio;
    let base = |ratio: &str, edges| Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 1.5,
        ratio: Ratio::parse(ratio).expect("a ratio"),
        edges,
        direction: Same,
    };
    [("hexagon, 2:1 × 3", base("2", 3)), ("11 sides, 11/3 × 3", base("11/3", 3))]
}

/// Table: centre height error → the smallest diameter's change and the turn.
pub fn height_table() -> String {
    let mut t = String::from(
        "| setup (R1 50, R2 10, depth 1.5 mm) | height error | smallest diameter grows by | section turned by |\n|---|---|---|---|\n",
    );
    for (name, s) in setups() {
        let base = smallest_diameter(&s);
        for h in [0.1, 0.5, 1.0, 2.0] {
            let (e, turn) = with_centre_height(&s, h);
            let grow_um = (smallest_diameter(&e) - base) * 1000.0;
            t += &format!("| {name} | {h:.1} mm | {grow_um:.1} µm | {:.2}° |\n", turn.to_degrees());
        }
    }
    t
}

/// Table: the cutter's axis tilted toward the work, and the cutter's real R1
/// 0.5 mm under the plan's, against the part.
pub fn tilt_and_r1_table() -> String {
    let mut t = String::from(
        "| setup (R1 50, R2 10, depth 1.5 mm) | axes tilted 0.1° toward the work: over 25 mm of length the flats are nearer the centre by | R1 0.5 mm under the plan's: flat bulge, planned → cut | the same: corner diameter, planned → cut |\n|---|---|---|---|\n",
    );
    for (name, s) in setups() {
        let p = summary(&s);
        let base = 2.0 * p.inscribed_radius;
        // 25 mm along the work the centre distance is 25·tan(0.1°) smaller
        let closer = 25.0 * 0.1f64.to_radians().tan();
        let tilted = Setup { depth_mm: s.depth_mm + closer, ..s };
        let taper_um = (base - smallest_diameter(&tilted)) / 2.0 * 1000.0;
        // the depth is fed from the tip touching the stock, so the real cut
        // has the plan's depth with the real, smaller R1
        let real = Setup { cutter_radius_mm: s.cutter_radius_mm - 0.5, ..s };
        let r = summary(&real);
        t += &format!(
            "| {name} | {taper_um:.0} µm | {:+.1} → {:+.1} µm | {:.3} → {:.3} mm |\n",
            p.flat_deviation * 1000.0,
            r.flat_deviation * 1000.0,
            2.0 * p.circumscribed_radius,
            2.0 * r.circumscribed_radius
        );
    }
    t
}

fn summary(s: &Setup) -> super::SectionSummary {
    Section::ideal_sector(s, Section::default_bins(s.sides())).summary()
}

/// The generated pages: (file name under docs/src/generated, text).
pub fn book_pages() -> Vec<(&'static str, String)> {
    vec![("spindle-height.md", height_table()), ("spindle-tilt.md", tilt_and_r1_table())]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_centre_height_error_cuts_the_ideal_pass_of_the_longer_centre_distance_turned_by_beta() {
        for (_, s) in setups() {
            let h = 0.8;
            let (e, beta) = with_centre_height(&s, h);
            let (x0, r1) = (s.centre_distance(), s.cutter_radius_mm);
            for i in 0..50 {
                let a = -0.2 + 0.008 * i as f64;
                // the tip with the cutter's axis at (X0, h), its phase counted
                // from the tilted line of centres
                let theta = beta + s.direction.sign() * s.gr() * a;
                let (sa, ca) = a.sin_cos();
                let (lx, ly) = (x0 - r1 * theta.cos(), h - r1 * theta.sin());
                let raised = (lx * ca + ly * sa, -lx * sa + ly * ca);
                let (px, py) = e.tip(a, 0.0);
                let (sb, cb) = beta.sin_cos();
                let turned = (px * cb - py * sb, px * sb + py * cb);
                assert!((raised.0 - turned.0).abs() < 1e-12 && (raised.1 - turned.1).abs() < 1e-12, "a = {a}");
            }
        }
    }

    #[test]
    fn a_height_error_is_second_order_and_a_tilt_toward_the_work_first_order() {
        let (_, s) = setups()[0];
        let base = smallest_diameter(&s);
        let grow = |h| smallest_diameter(&with_centre_height(&s, h).0) - base;
        // doubling the error quadruples the effect (h²/2X0 per side)
        let (g1, g2) = (grow(0.5), grow(1.0));
        assert!((g2 / g1 - 4.0).abs() < 0.05, "{g1} {g2}");
        assert!((g1 - 2.0 * 0.25 / (2.0 * s.centre_distance())).abs() < 2e-4, "{g1}");
        // 0.1 mm nearer the work: about 0.2 mm off the diameter
        let nearer = Setup { depth_mm: s.depth_mm + 0.1, ..s };
        assert!((base - smallest_diameter(&nearer) - 0.2).abs() < 0.02);
    }
}

#[cfg(test)]
mod book {
    #[test]
    fn the_spindle_tables_in_the_book_match_the_model() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/src/generated");
        for (name, text) in super::book_pages() {
            let committed = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
            assert!(
                committed == text,
                "docs/src/generated/{name} differs from the model: run `cargo run -p polyturn-host --example spindle_book` and commit it"
            );
        }
    }
}
