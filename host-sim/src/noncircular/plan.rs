//! Checks a tool path against the X axis and the polygon, and picks the
//! path to cut: sharp corners when the axis allows them at this speed,
//! otherwise the least corner rounding that fits.

use super::path::{line, Path, Polygon, ToolPath};
use super::rounded::Rounded;
use std::f64::consts::TAU;

/// What one path costs and what it cuts.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// mm/s and mm/s² at the lathe speed asked for
    pub peak_speed: f64,
    pub peak_accel: f64,
    /// the fastest lathe speed (rpm) within the axis limits, and which binds
    pub max_rpm: f64,
    pub limit: Limit,
    /// most material left above the polygon (the corner rounding), mm
    pub excess: f64,
    /// deepest cut below the polygon, mm (a gouge if above zero)
    pub overcut: f64,
    /// lowest and highest tool radius, mm
    pub travel: (f64, f64),
    /// largest jump in X speed (mm/s) at a cut/link junction, measured
    /// from one-sided differences of the position
    pub velocity_jump: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Limit {
    Speed,
    Accel,
}

/// Samples per period for the peaks, and per revolution for the section.
const PEAK_SAMPLES: usize = 4096;
const SECTION_SAMPLES: usize = 8192;

/// The axis: mm/s and mm/s², and the lathe speed asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub rpm: f64,
    pub max_speed: f64,
    pub max_accel: f64,
}

pub fn evaluate(path: &dyn ToolPath, axis: Axis) -> Evaluation {
    let w = axis.rpm / 60.0 * TAU;
    let (mut slope, mut curv, mut lo, mut hi) = (0.0f64, 0.0f64, f64::INFINITY, f64::NEG_INFINITY);
    let d = path.period();
    // the cut's ends (its steepest, most curved points) and a dense grid
    for phi in (0..PEAK_SAMPLES).map(|k| d * k as f64 / PEAK_SAMPLES as f64).chain(path.junctions()) {
        let [g, g1, g2] = path.at(phi);
        (slope, curv, lo, hi) = (slope.max(g1.abs()), curv.max(g2.abs()), lo.min(g), hi.max(g));
    }
    let (excess, overcut) = section_error(path);
    // X speed scales with ω and X acceleration with ω² (the path is fixed
    // in lathe angle), so each limit gives a top lathe speed.
    let by_speed = 60.0 / TAU * axis.max_speed / slope.max(1e-12);
    let by_accel = 60.0 / TAU * (axis.max_accel / curv.max(1e-12)).sqrt();
    let (max_rpm, limit) = if by_speed <= by_accel { (by_speed, Limit::Speed) } else { (by_accel, Limit::Accel) };
    Evaluation {
        peak_speed: slope * w,
        peak_accel: curv * w * w,
        max_rpm,
        limit,
        excess,
        overcut,
        travel: (lo, hi),
        velocity_jump: velocity_jump(path, w),
    }
}

/// (excess, overcut) of the path's section against the polygon, sampled
/// densely and at every corner.
fn section_error(path: &dyn ToolPath) -> (f64, f64) {
    let n = path.polygon().sides;
    let corners = (0..n).map(|k| (k as f64 + 0.5) * TAU / n as f64);
    let grid = (0..SECTION_SAMPLES).map(|k| TAU * k as f64 / SECTION_SAMPLES as f64);
    grid.chain(corners).fold((0.0f64, 0.0f64), |(ex, oc), phi| {
        let dev = path.section(phi) - path.polygon().radius(phi);
        (ex.max(dev), oc.max(-dev))
    })
}

/// The largest change of X speed across any cut/link junction, from
/// one-sided differences of position (independent of the derivatives the
/// path reports about itself).
fn velocity_jump(path: &dyn ToolPath, w: f64) -> f64 {
    let e = 1e-6;
    let g = |phi: f64| path.at(phi)[0];
    let jump = |x: f64| ((g(x + e) - g(x)) / e - (g(x) - g(x - e)) / e).abs() * w;
    path.junctions().into_iter().map(jump).fold(0.0, f64::max)
}

/// The path to cut.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    Sharp(Path, Evaluation),
    /// the smallest fillet within the limits; its evaluation's `max_rpm`
    /// is below the speed asked for only if no fillet fits at all. The last
    /// field is the fastest lathe speed sharp corners would allow.
    Rounded(Rounded, Evaluation, f64),
}

/// Tolerance for "reproduces the polygon" (the 1 µm).
pub const TOLERANCE_MM: f64 = 1e-3;

/// Sharp corners if the axis allows them at this speed; else the smallest
/// corner fillet that fits (bisection: both limits ease as ρ grows).
pub fn plan(polygon: Polygon, m: u32, axis: Axis) -> Outcome {
    let (path, sharp) = best_link(polygon, m, axis);
    if sharp.max_rpm >= axis.rpm {
        return Outcome::Sharp(path, sharp);
    }
    let fillet = |rho: f64| Rounded { polygon, radius_mm: rho };
    let (mut lo, mut hi) = (0.0, 0.999 * polygon.apothem_mm);
    for _ in 0..40 {
        let mid = (lo + hi) / 2.0;
        if evaluate(&fillet(mid), axis).max_rpm >= axis.rpm {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Outcome::Rounded(fillet(hi), evaluate(&fillet(hi), axis), sharp.max_rpm)
}

const LINK_CHOICES: u32 = 24;

/// The sharp-cornered path whose links allow the highest lathe speed
/// without gouging (ties: the least X travel). The links' end acceleration
/// runs from the line's curvature (C2) down to −2× it: less lets a link
/// turn back sooner, so it rises less and moves slower (the noncircular
/// turning note asks for continuous position and velocity; the
/// acceleration may step, within the limit).
pub fn best_link(polygon: Polygon, m: u32, axis: Axis) -> (Path, Evaluation) {
    let h = polygon.half_side();
    let curvature = line(polygon.apothem_mm, h)[2];
    let candidates =
        (0..=LINK_CHOICES).map(|k| Path::new(polygon, m, h, curvature * (1.0 - 3.0 * k as f64 / LINK_CHOICES as f64)));
    candidates
        .map(|p| {
            let e = evaluate(&p, axis);
            (p, e)
        })
        .filter(|(_, e)| e.overcut <= TOLERANCE_MM / 10.0)
        .fold(None, |best: Option<(Path, Evaluation)>, c| match best {
            Some(b) if (b.1.max_rpm, -b.1.travel.1) >= (c.1.max_rpm, -c.1.travel.1) => Some(b),
            _ => Some(c),
        })
        .unwrap_or_else(|| {
            let p = Path::smooth(polygon, m, h);
            let e = evaluate(&p, axis);
            (p, e)
        })
}
