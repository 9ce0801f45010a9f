//! `polyturn compensate`: plan the X axis that makes the flats straight.

use super::errors::{CliError, CliResult};
use super::setup_args::SetupArgs;
use super::values::{rpm, within};
use crate::compensate::{plan, section, Limit};
use crate::geometry::Section;
use serde_json::json;

#[derive(clap::Args, Debug)]
pub struct CompensateArgs {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Lathe speed while cutting, rpm
    #[arg(long, value_name = "RPM", value_parser = rpm(6000.0))]
    pub rpm: f64,
    /// The X axis's top speed, mm/s
    #[arg(long, value_name = "MM/S", value_parser = within(0.001, 1e4, "mm/s"))]
    pub x_max_speed: f64,
    /// The X axis's top acceleration, mm/s^2
    #[arg(long, value_name = "MM/S^2", value_parser = within(0.001, 1e6, "mm/s^2"))]
    pub x_max_accel: f64,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: CompensateArgs) -> CliResult<String> {
    let setup = a.setup.setup()?;
    let (rpm, v, acc) = (a.rpm, a.x_max_speed, a.x_max_accel);
    let p = plan(&setup, rpm, v, acc);
    let before = Section::ideal(&setup, 1024).summary().flat_deviation;
    let after = match p.limited_by {
        None => Some(section(&setup, &p, 1024).summary().flat_deviation),
        Some(_) => None,
    };
    let why = |l: Limit| {
        match l {
        Limit::Overlap => "two edges cut at the same time, and one X axis cannot serve both: fewer edges, a larger cutter or the other direction".to_string(),
        // (with one edge, fewer is no remedy: the ratio is)
        Limit::Gouge if setup.edges == 1 => "the link between passes would cut into the flats: another ratio".to_string(),
        Limit::Gouge => "the link between passes would cut into the flats: fewer edges or another ratio".to_string(),
        Limit::Speed => format!("X speed {:.1} mm/s exceeds {v} mm/s: {}", p.peak_x_speed, allows(p.max_rpm)),
        Limit::Accel => format!("X acceleration {:.0} mm/s^2 exceeds {acc} mm/s^2: {}", p.peak_x_accel, allows(p.max_rpm)),
    }
    };
    // A plan the axis cannot follow is refused, naming what limits it
    // (the X axis's speed or acceleration, or the setup's edges).
    if let Some(l) = p.limited_by {
        let flag = match l {
            Limit::Gouge if setup.edges == 1 => "ratio",
            Limit::Overlap | Limit::Gouge => "edges",
            Limit::Speed => "x-max-speed",
            Limit::Accel => "x-max-accel",
        };
        return Err(CliError::flag(
            flag,
            format!("cannot straighten these flats (deviation stays {before:+.4} mm): {}", why(l)),
        ));
    }
    if a.json {
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
    // rounded first, so that a deviation under 0.05 µm is +0.0000, not -0.0000
    let after = (after.unwrap_or(before) * 1e4).round() / 1e4 + 0.0;
    Ok(format!(
        "flats straightened: deviation {before:+.4} mm -> {after:+.4} mm\nX travel {:.3} mm, peak X speed {:.1} mm/s, peak X acceleration {:.0} mm/s^2 (allows {})",
        p.x_travel, p.peak_x_speed, p.peak_x_accel, up_to(p.max_rpm)
    ))
}

/// The lathe speed the X axis allows, in a refusal: below the 1 rpm
/// floor, that the axis is at fault.
fn allows(max_rpm: Option<f64>) -> String {
    match max_rpm {
        Some(r) if r < 1.0 => "this X axis cannot follow even at 1 rpm: give it more speed and acceleration".into(),
        m => format!("at most {}", up_to(m)),
    }
}

/// The lathe speed the X axis allows, or that it sets no limit.
fn up_to(max_rpm: Option<f64>) -> String {
    match max_rpm {
        Some(r) => format!("up to {r:.0} rpm"),
        None => "any lathe speed: the X axis does not move".into(),
    }
}
