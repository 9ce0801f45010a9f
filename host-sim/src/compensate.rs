//! Flat sides whatever the ratio and cutter (Foale, "Turning polygons on a
//! lathe", 2022: "a CNC lathe
//! can make the flats perfectly flat by moving the X axis in step"). The
//! cross-slide sets the centre distance X so that each tip moves along its
//! flat's straight line while it cuts, and links passes smoothly between.
//!
//! In pass-local lathe angle τ (0 at the pass's closest approach) the tip is
//! at P = X(τ)·e^{−iτ} − R1·e^{ikτ} (see `geometry`); Re P = R_c, the flat,
//! gives X(τ) = (R_c + R1·cos kτ) / cos τ. Passes repeat every Δ = 2π/(GR·Z)
//! of lathe angle, so X is even and Δ-periodic: one pass and its link.

use crate::geometry::{Section, Setup};
use std::f64::consts::{PI, TAU};

/// What stops the flats from being made straight, if anything.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Limit {
    /// two edges cut at once: one X axis cannot serve both
    Overlap,
    /// the link between passes would cut into the finished flats
    Gouge,
    Speed,
    Accel,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct Plan {
    /// X offset from the nominal centre distance over one pass period,
    /// sampled evenly in lathe angle from −Δ/2 to Δ/2, mm
    #[serde(skip)]
    pub x: Vec<f64>,
    pub period_rad: f64,
    pub cut_half_window_rad: f64,
    pub x_travel: f64,
    pub peak_x_speed: f64,
    pub peak_x_accel: f64,
    pub limited_by: Option<Limit>,
    /// the fastest lathe speed the X limits allow, rpm
    pub max_rpm: Option<f64>,
}

fn x_cut(s: &Setup, tau: f64) -> (f64, f64) {
    // value and derivative of (R_c + R1 cos kτ) / cos τ
    let (rc, r1, k) = (s.stock_radius_mm - s.depth_mm, s.cutter_radius_mm, s.k());
    let (num, den) = (rc + r1 * (k * tau).cos(), tau.cos());
    let dnum = -r1 * k * (k * tau).sin();
    (num / den, (dnum * den + num * tau.sin()) / (den * den))
}

/// τ at which the tip, on the flat, reaches a corner (polar angle π/N).
fn corner_tau(s: &Setup) -> Option<f64> {
    let rc = s.stock_radius_mm - s.depth_mm;
    let half = rc * (PI / s.sides() as f64).tan();
    let y = |t: f64| {
        let (x, _) = x_cut(s, t);
        (-x * t.sin() - s.cutter_radius_mm * (s.k() * t).sin()).abs()
    };
    let limit = PI / s.gr() / s.edges as f64; // half the pass spacing
    let (mut lo, mut hi) = (0.0, limit.min(1.4));
    if y(hi) < half {
        return None; // never reaches the corner within its share of time
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if y(mid) < half {
            lo = mid
        } else {
            hi = mid
        }
    }
    Some(hi)
}

/// Plans X for `setup` at `rpm`, within `v_max` mm/s and `a_max` mm/s².
pub fn plan(setup: &Setup, rpm: f64, v_max: f64, a_max: f64) -> Plan {
    let period = TAU / (setup.gr() * setup.edges as f64);
    let x0 = setup.centre_distance();
    let samples = 4000usize;
    let tc = corner_tau(setup);
    let mut plan = Plan {
        x: vec![0.0; samples + 1],
        period_rad: period,
        cut_half_window_rad: tc.unwrap_or(0.0),
        x_travel: 0.0,
        peak_x_speed: 0.0,
        peak_x_accel: 0.0,
        limited_by: None,
        max_rpm: None,
    };
    let Some(tc) = tc.filter(|t| 2.0 * t < period) else {
        plan.limited_by = Some(Limit::Overlap);
        return plan;
    };
    // Cubic Hermite link from (tc, X, X') to (Δ − tc, X, −X'), the next pass.
    let (xe, de) = x_cut(setup, tc);
    let gap = period - 2.0 * tc;
    let link = |u: f64| {
        let t = u / gap;
        let (h10, h01, h11) = (t * t * t - 2.0 * t * t + t, -2.0 * t * t * t + 3.0 * t * t, t * t * t - t * t);
        let h00 = 1.0 - h01;
        h00 * xe + h10 * gap * de + h01 * xe + h11 * gap * (-de)
    };
    for (i, x) in plan.x.iter_mut().enumerate() {
        let tau = -period / 2.0 + period * i as f64 / samples as f64;
        *x = if tau.abs() <= tc { x_cut(setup, tau).0 } else { link(tau.abs() - tc) } - x0;
    }
    let w = rpm / 60.0 * TAU; // rad/s of the lathe
    let h = period / samples as f64;
    for i in 1..samples {
        let v = (plan.x[i + 1] - plan.x[i - 1]) / (2.0 * h) * w;
        let a = (plan.x[i + 1] - 2.0 * plan.x[i] + plan.x[i - 1]) / (h * h) * w * w;
        plan.peak_x_speed = plan.peak_x_speed.max(v.abs());
        plan.peak_x_accel = plan.peak_x_accel.max(a.abs());
    }
    let (lo, hi) = plan.x.iter().fold((f64::MAX, f64::MIN), |(l, u), &v| (l.min(v), u.max(v)));
    plan.x_travel = hi - lo;
    // X speed goes with the lathe speed and X acceleration with its
    // square: each limit scales the speed asked for by its own factor
    let (by_speed, by_accel) = (v_max / plan.peak_x_speed, (a_max / plan.peak_x_accel).sqrt());
    // An X motion of zero speed and acceleration sets no limit (None),
    // never an infinite one.
    plan.max_rpm = Some(rpm * by_speed.min(by_accel)).filter(|r| r.is_finite());
    // past both limits, the one that sets the top speed is at fault:
    // raising the other would change nothing
    let speed_binds = plan.peak_x_speed > v_max && by_speed <= by_accel;
    if gouges(setup, &plan) {
        plan.limited_by = Some(Limit::Gouge);
    } else if speed_binds {
        plan.limited_by = Some(Limit::Speed);
    } else if plan.peak_x_accel > a_max {
        // (speed past its limit and not binding: acceleration is past a tighter one)
        plan.limited_by = Some(Limit::Accel);
    }
    plan
}

/// Tip position over one pass period with the planned X.
pub fn trace(setup: &Setup, plan: &Plan) -> Vec<(f64, f64)> {
    let (x0, r1, k) = (setup.centre_distance(), setup.cutter_radius_mm, setup.k());
    let n = plan.x.len() - 1;
    (0..=n)
        .map(|i| {
            let tau = -plan.period_rad / 2.0 + plan.period_rad * i as f64 / n as f64;
            let x = x0 + plan.x[i];
            (x * tau.cos() - r1 * (k * tau).cos(), -x * tau.sin() - r1 * (k * tau).sin())
        })
        .collect()
}

/// The section the compensated motion cuts (every pass is this one rotated).
pub fn section(setup: &Setup, plan: &Plan, bins_per_side: usize) -> Section {
    Section::from_pass(setup, &trace(setup, plan), bins_per_side)
}

/// Whether the link between passes dips inside the straight-sided polygon.
fn gouges(setup: &Setup, plan: &Plan) -> bool {
    let (rc, n) = (setup.stock_radius_mm - setup.depth_mm, setup.sides() as f64);
    trace(setup, plan).iter().any(|&(x, y)| {
        let (r, phi) = (x.hypot(y), y.atan2(x));
        let rel = (phi + PI / n).rem_euclid(TAU / n) - PI / n; // from the nearest flat's middle
        r < rc / rel.cos() - 1e-6
    })
}

/// The plan as a cam table for the core: `points` X positions (steps) over
/// a period in lathe counts, index 0 at a pass's middle. X repeats every
/// pass, so when a pass spans whole counts the table covers just one (finer
/// for the same size); otherwise the pattern's whole period.
pub fn cam_table(setup: &Setup, plan: &Plan, counts_per_rev: u32, steps_per_mm: f64, points: usize) -> (Vec<i32>, u32) {
    let (sides, revs) = setup.pattern();
    let period_counts = crate::noncircular::table::shortest_period(revs, counts_per_rev, sides);
    let n = points.min(period_counts as usize).max(2);
    let samples = plan.x.len() - 1;
    let table = (0..n)
        .map(|j| {
            let a = TAU * period_counts as f64 / counts_per_rev as f64 * j as f64 / n as f64;
            let tau = (a + plan.period_rad / 2.0).rem_euclid(plan.period_rad) - plan.period_rad / 2.0;
            let at = (tau + plan.period_rad / 2.0) / plan.period_rad * samples as f64;
            let (i, f) = (at.floor() as usize, at - at.floor());
            let (x0, x1) = (plan.x[i.min(samples)], plan.x[(i + 1).min(samples)]);
            ((x0 + (x1 - x0) * f) * steps_per_mm).round() as i32
        })
        .collect();
    (table, period_counts)
}

pub mod table;

#[cfg(test)]
mod tests;
