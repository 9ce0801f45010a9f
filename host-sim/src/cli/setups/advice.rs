//! What `setups` warns of: figures a machinist should
//! not take as a setup. A warning is a line, not a refusal: the table is
//! still the truth about the geometry, and exit status stays 0.

use crate::planner::{Candidate, Request};
use polyturn_sync::Config;

/// The largest cutter radius worth listing as buildable, mm. The cutter
/// turns in the space the lathe swings the work in, so its diameter is
/// bounded by the swing over the bed: 500 mm is a 20-inch lathe's, larger
/// than any home lathe (their swings are about 180 to 360 mm). A smallest
/// R1 past it (1470 mm for some setups) is a wheel no lathe here can turn.
pub const MAX_CUTTER_RADIUS_MM: f64 = 250.0;

/// `--max-tip-speed`'s default, m/s (the figure): 1200 m/min is
/// already the top of carbide's cutting speeds, in aluminium (steel takes
/// a fraction of it), so a tip past it is no cutting speed.
pub const DEFAULT_MAX_TIP_SPEED: f64 = 20.0;

/// The warning ceilings, from the command line.
pub struct Limits {
    /// m/s: `--max-tip-speed`
    pub tip_speed: f64,
    /// rpm: `--max-cutter-rpm`
    pub cutter_rpm: f64,
}

/// The cutter's top speed with the firmware's default settings: the step
/// rate the board allows over the steps of one cutter turn (200 000
/// steps/s at 3200 steps, 3750 rpm). `simulate` runs that motor, and
/// refuses a lathe speed that would need more of it.
pub fn default_max_cutter_rpm() -> f64 {
    let c = Config::default();
    c.max_step_rate_hz as f64 * 60.0 / c.motor_steps_per_rev as f64
}

/// Each limit a row passes, as a sentence (the row's own warnings).
pub fn row(c: &Candidate, l: &Limits) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(v) = c.peak_tip_speed.filter(|&v| v > l.tip_speed) {
        out.push(format!("tip speed {v:.2} m/s is above --max-tip-speed {} m/s", l.tip_speed));
    }
    if let Some(v) = c.cutter_rpm.filter(|&v| v > l.cutter_rpm) {
        out.push(format!("cutter speed {v:.0} rpm is above --max-cutter-rpm {}", l.cutter_rpm));
    }
    if let Some(v) = c.min_cutter_radius.filter(|&v| v > MAX_CUTTER_RADIUS_MM) {
        out.push(format!("smallest cutter radius {v} mm is more than a lathe swings ({MAX_CUTTER_RADIUS_MM} mm)"));
    }
    out
}

/// One warning per limit some rows pass: how many, the worst
/// figure, and what to change.
pub fn warnings(found: &[Candidate], req: &Request, l: &Limits) -> Vec<String> {
    let n = found.len();
    let over = |f: fn(&Candidate) -> Option<f64>, limit: f64| {
        let v: Vec<f64> = found.iter().filter_map(f).filter(|&v| v > limit).collect();
        (!v.is_empty()).then(|| (v.len(), v.iter().copied().fold(f64::MIN, f64::max)))
    };
    let rpm = req.rpm.unwrap_or(0.0);
    let mut out = Vec::new();
    if let Some((k, worst)) = over(|c| c.peak_tip_speed, l.tip_speed) {
        out.push(format!(
            "{k} of {n} setups cut faster than --max-tip-speed {} m/s at --rpm {rpm} (up to {worst:.2} m/s): lower --rpm, or take a row within it",
            l.tip_speed
        ));
    }
    if let Some((k, worst)) = over(|c| c.cutter_rpm, l.cutter_rpm) {
        out.push(format!(
            "{k} of {n} setups turn the cutter faster than --max-cutter-rpm {} at --rpm {rpm} (up to {worst:.0} rpm): lower --rpm, or take a row within it",
            l.cutter_rpm
        ));
    }
    let assumed = crate::planner::default_cutter(req.stock_radius);
    if req.cutter_radius.is_none() && assumed > MAX_CUTTER_RADIUS_MM {
        out.push(format!(
            "the assumed cutter radius {assumed} mm is more than a lathe swings ({MAX_CUTTER_RADIUS_MM} mm): give --cutter-radius for yours"
        ));
    }
    if let Some((k, worst)) = over(|c| c.min_cutter_radius, MAX_CUTTER_RADIUS_MM) {
        out.push(format!(
            "{k} of {n} setups need a cutter radius over {MAX_CUTTER_RADIUS_MM} mm for --tolerance {} mm (up to {worst:.0} mm in min R1): no home lathe swings a cutter that size (a 20-inch lathe swings 500 mm); raise --tolerance, or take a row within it",
            req.tolerance
        ));
    }
    out
}
