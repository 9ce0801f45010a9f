//! `polyturn compensate`: plan the X axis that makes the flats straight.

use super::args::{Args, CliError, CliResult};
use super::geometry::setup_from;
use crate::compensate::{plan, section, Limit};
use crate::geometry::Section;
use serde_json::json;

pub const USAGE: &str = "polyturn compensate --cutter-radius R1 --stock-radius R2 --depth DOC --ratio GR --edges Z --direction same|opposite --rpm RPM --x-max-speed V(mm/s) --x-max-accel A(mm/s^2) [--json]";
const VALUED: &[&str] =
    &["cutter-radius", "stock-radius", "depth", "ratio", "edges", "direction", "rpm", "x-max-speed", "x-max-accel"];

pub fn run(argv: &[String]) -> CliResult<String> {
    let a = Args::parse(argv, VALUED, &["json"])?;
    let setup = setup_from(&a)?;
    let need = |f: &str, unit: &str| -> CliResult<f64> {
        a.number(f, 0.0, 1e9, true, unit)?.ok_or_else(|| CliError::flag(f, "is required"))
    };
    let (rpm, v, acc) = (need("rpm", "rpm")?, need("x-max-speed", "mm/s")?, need("x-max-accel", "mm/s^2")?);
    let p = plan(&setup, rpm, v, acc);
    let before = Section::ideal(&setup, 1024).summary().flat_deviation;
    let after = match p.limited_by {
        None => Some(section(&setup, &p, 1024).summary().flat_deviation),
        Some(_) => None,
    };
    let why = |l: Limit| {
        match l {
        Limit::Overlap => "two edges cut at the same time, and one X axis cannot serve both: fewer edges, a larger cutter or the other direction".to_string(),
        Limit::Gouge => "the link between passes would cut into the flats".to_string(),
        Limit::Speed => format!("X speed {:.1} mm/s exceeds {v} mm/s: at most {:.0} rpm", p.peak_x_speed, p.max_rpm.unwrap_or(0.0)),
        Limit::Accel => format!("X acceleration {:.0} mm/s^2 exceeds {acc} mm/s^2: at most {:.0} rpm", p.peak_x_accel, p.max_rpm.unwrap_or(0.0)),
    }
    };
    if a.has("json") {
        return Ok(json!({
            "flat_deviation_before": before,
            "flat_deviation_after": after,
            "x_travel": p.x_travel,
            "peak_x_speed": p.peak_x_speed,
            "peak_x_accel": p.peak_x_accel,
            "limited_by": p.limited_by,
            "reason": p.limited_by.map(why),
            "max_rpm": p.max_rpm,
        })
        .to_string());
    }
    Ok(match (p.limited_by, after) {
        (None, Some(d)) => format!(
            "flats straightened: deviation {before:+.4} mm -> {d:+.4} mm\nX travel {:.3} mm, peak X speed {:.1} mm/s, peak X acceleration {:.0} mm/s^2 (allows up to {:.0} rpm)",
            p.x_travel, p.peak_x_speed, p.peak_x_accel, p.max_rpm.unwrap_or(0.0)
        ),
        (Some(l), _) => format!("flat deviation stays {before:+.4} mm: {}", why(l)),
        (None, None) => format!("flat deviation stays {before:+.4} mm"),
    })
}
