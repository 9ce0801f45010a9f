//! What `polyturn cam` is asked, checked before any planning: each flag in
//! its range, and the flags that depend on each other together.

use super::CamArgs;
use crate::cli::errors::{CliError, CliResult};
use crate::cli::x_table::rates;
use crate::noncircular::path::Polygon;
use crate::noncircular::plan::Axis;
use crate::noncircular::{check, smallest_m};
use polyturn_sync::cam::CAM_POINTS;

/// The largest m: the table's CAM_POINTS give each cut at most
/// CAM_POINTS / m points (the cut is 1/m of the period in the best case),
/// and a flat needs a few: 8 of them at m = 128. (It also bounds the plan,
/// whose section takes the minimum over m turns: m = 999 took 18 s.)
const MAX_M: u32 = (CAM_POINTS / 8) as u32;

pub struct Request {
    pub polygon: Polygon,
    pub m: u32,
    pub axis: Axis,
    pub steps_per_mm: f64,
    pub counts_per_rev: u32,
    /// the axis's limits in whole steps/s and steps/s^2, for the table
    pub rates: (u32, u32),
}

/// m as typed, any whole number: `request` refuses it knowing N.
pub fn turns(s: &str) -> Result<u32, String> {
    crate::cli::values::unplussed(s)
        .and_then(|t| t.parse::<u32>().ok())
        .ok_or_else(|| "must be a whole number in 2..=N-1 (N is --sides)".into())
}

pub fn request(a: &CamArgs) -> CliResult<Request> {
    let sides = a.sides;
    let m = match a.m {
        Some(m) if m >= sides || m > MAX_M => return Err(m_range(sides, m)),
        Some(m) => check(sides, m).map(|_| m).map_err(|e| CliError::flag("m", e.describe()))?,
        None => smallest_m(sides).map_err(|e| CliError::flag("sides", e.describe()))?,
    };
    let axis = Axis { rpm: a.rpm, max_speed: a.x_max_speed, max_accel: a.x_max_accel };
    let spm = a.board.steps_per_mm();
    let rates = rates(axis.max_speed, axis.max_accel, spm)?;
    Ok(Request {
        polygon: Polygon { sides, apothem_mm: a.inscribed_radius },
        m,
        axis,
        steps_per_mm: spm,
        counts_per_rev: a.board.encoder_counts(),
        rates,
    })
}

/// Why m is outside 2..=min(N - 1, MAX_M). The top speed is set by the
/// cuts, which m leaves alone (m and m + N cut the same sides in the same
/// order, i·m mod N), so a larger m buys nothing but turns.
fn m_range(sides: u32, m: u32) -> CliError {
    let why = if sides - 1 <= MAX_M {
        format!("m and m - {sides} cut the sides in the same order at the same top speed, the larger in more turns with a coarser table")
    } else {
        format!("the table's {CAM_POINTS} points give each cut at most {CAM_POINTS}/m of them, and a flat needs 8")
    };
    let hi = (sides - 1).min(MAX_M);
    CliError::flag("m", format!("must be in 2..={hi} for {sides} sides: {why} (got '{m}')"))
}
