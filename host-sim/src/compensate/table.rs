//! The compensating X motion as a cam table the board runs (the same
//! `polyturn-cam-1` file `polyturn cam` writes), and how far the core's
//! reading of it (linear between points, whole steps) is from the plan.

use super::{cam_table, Plan};
use crate::geometry::Setup;
use crate::noncircular::table::{CamFile, MadeFor, FORMAT};
use polyturn_sync::cam::CAM_POINTS;
use std::f64::consts::TAU;

/// The plan as the board's cam table: `rates` are the X axis's limits in
/// steps/s and steps/s² that the table declares (`cam_upload`).
pub fn cam_file(setup: &Setup, plan: &Plan, counts_per_rev: u32, steps_per_mm: f64, rates: (u32, u32)) -> CamFile {
    let (points, period_counts) = cam_table(setup, plan, counts_per_rev, steps_per_mm, CAM_POINTS);
    CamFile {
        format: FORMAT.into(),
        counts_per_rev,
        period_counts,
        steps_per_mm,
        max_rate_hz: rates.0,
        max_accel: rates.1,
        points,
        cutter: Some(MadeFor { ratio: setup.ratio.to_string(), edges: setup.edges, direction: Some(setup.direction) }),
    }
}

/// The plan's X offset (mm) at lathe angle `a` from a pass's middle,
/// linear between its samples.
fn planned(plan: &Plan, a: f64) -> f64 {
    let p = plan.period_rad;
    let samples = plan.x.len() - 1;
    let tau = (a + p / 2.0).rem_euclid(p) - p / 2.0;
    let at = (tau + p / 2.0) / p * samples as f64;
    let (i, f) = (at.floor() as usize, at - at.floor());
    let (x0, x1) = (plan.x[i.min(samples)], plan.x[(i + 1).min(samples)]);
    x0 + (x1 - x0) * f
}

/// Largest |X the core takes from `table` − X the plan asks| (mm) over the
/// table's period, `samples` lathe angles: what the table's whole steps
/// and linear interpolation add to the plan.
pub fn error_mm(plan: &Plan, table: &CamFile, samples: usize) -> f64 {
    let span = TAU * table.period_counts as f64 / table.counts_per_rev as f64;
    (0..samples)
        .map(|k| span * k as f64 / samples as f64)
        .map(|a| (table.radius(0.0, a) - planned(plan, a)).abs())
        .fold(0.0, f64::max)
}
