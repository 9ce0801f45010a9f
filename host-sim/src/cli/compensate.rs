//! `polyturn compensate`: plan the X axis that makes the flats straight,
//! and with `--table` write it as a cam table for the board.

use super::errors::{CliError, CliResult};
use super::limits::floor_tenth;
use super::output::Outputs;
use super::setup_args::SetupArgs;
use super::values::{rpm, within};
use super::x_table::{board_takes, rates, TableArgs};
use crate::cli::cam::{TABLE_COARSE_MM, TABLE_REFUSED_MM};
use crate::compensate::{plan, section, table, Limit, Plan};
use crate::geometry::Section;
use crate::geometry::Setup;
use crate::noncircular::table::CamFile;
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
    /// The board's X axis (with --table, its speed and acceleration are
    /// checked against what the board emits)
    #[command(flatten)]
    pub board: TableArgs,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: CompensateArgs) -> CliResult<String> {
    a.board.only_with_a_table()?;
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
        Limit::Speed => format!("X speed {:.2} mm/s exceeds {v} mm/s: {}", p.peak_x_speed, allows(p.max_rpm)),
        Limit::Accel => format!("X acceleration {:.1} mm/s^2 exceeds {acc} mm/s^2: {}", p.peak_x_accel, allows(p.max_rpm)),
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
    no_straighter(before, after)?;
    let table = match &a.board.table {
        Some(_) => Some(board_table(&setup, &p, &a)?),
        None => None,
    };
    let mut files = Outputs::default();
    if let (Some(file), Some((t, _))) = (&a.board.table, &table) {
        files.add("table", file, serde_json::to_string(t).map_err(|e| CliError(e.to_string()))?)?;
    }
    let written = files.write()?;
    let table_json = table.as_ref().map(|(t, err)| {
        json!({"points": t.points.len(), "period_counts": t.period_counts, "counts_per_rev": t.counts_per_rev, "error_um": (err * 1e4).round() / 10.0})
    });
    if a.json {
        return Ok(written.report(
            json!({
                "flat_deviation_before": before,
                "flat_deviation_after": after,
                "x_travel": p.x_travel,
                "peak_x_speed": p.peak_x_speed,
                "peak_x_accel": p.peak_x_accel,
                "limited_by": p.limited_by,
                "reason": p.limited_by.map(why),
                "max_rpm": p.max_rpm,
                "table": table_json,
            })
            .to_string(),
        ));
    }
    // rounded first, so that a deviation under 0.05 µm is +0.0000, not -0.0000
    let after = (after.unwrap_or(before) * 1e4).round() / 1e4 + 0.0;
    let mut text = format!(
        "flats straightened: deviation {before:+.4} mm -> {after:+.4} mm\nX travel {:.3} mm, peak X speed {:.1} mm/s, peak X acceleration {:.0} mm/s^2 (allows {})",
        p.x_travel, p.peak_x_speed, p.peak_x_accel, up_to(p.max_rpm)
    );
    if let Some((t, err)) = &table {
        text += &table_line(t, *err);
    }
    if let Some(w) = written.wrote() {
        text += &format!("\n{w}");
    }
    Ok(written.report(text))
}

/// Flats the fixed axis already cuts as straight as the X motion would
/// (a ratio whose cutter barely turns): nothing to straighten, refused
/// rather than called straightened.
fn no_straighter(before: f64, after: Option<f64>) -> CliResult<()> {
    match after {
        Some(a) if a.abs() >= before.abs() => Err(CliError::flag(
            "ratio",
            format!("cuts flats the X motion cannot make straighter (deviation {before:+.4} mm on a fixed axis, {a:+.4} mm with it)"),
        )),
        _ => Ok(()),
    }
}

/// What the report says of the table written.
fn table_line(t: &CamFile, err_mm: f64) -> String {
    let fix = if err_mm > TABLE_COARSE_MM { format!(": {}", finer(t)) } else { String::new() };
    format!(
        "\ntable {} points over {} lathe counts; as the board interpolates it, {:.1} µm from the plan{fix}",
        t.points.len(),
        t.period_counts,
        err_mm * 1e3,
    )
}

/// What would make a coarse table finer: when its points are capped below
/// one a count, a shorter pattern (the cap binds, not the encoder).
fn finer(t: &CamFile) -> String {
    if (t.points.len() as u32) < t.period_counts {
        let turns = t.period_counts as f64 / t.counts_per_rev as f64;
        format!("the table's {} points are too few for an X motion that repeats every {turns:.2} lathe turns: a ratio whose pattern is shorter", t.points.len())
    } else {
        "raise --steps-per-mm or --encoder-cpr for a finer one".into()
    }
}

/// The plan as the board's cam table, and how far the board's reading of
/// it is from the plan (mm): refused when the board could not run it (its
/// X rate, the table's own checks) or it is further off than a `cam`
/// table may be.
fn board_table(setup: &Setup, p: &Plan, a: &CompensateArgs) -> CliResult<(CamFile, f64)> {
    let (spm, cpr) = (a.board.steps_per_mm(), a.board.encoder_counts());
    let t = table::cam_file(setup, p, cpr, spm, rates(a.x_max_speed, a.x_max_accel, spm)?);
    board_takes(&t)?;
    let err = table::error_mm(p, &t, 8192);
    if err > TABLE_REFUSED_MM {
        let (flag, fix) = if 1.0 / spm > TABLE_REFUSED_MM {
            ("steps-per-mm", "more steps per mm".to_string())
        } else if (t.points.len() as u32) < t.period_counts {
            ("ratio", finer(&t))
        } else {
            ("encoder-cpr", "a finer encoder".to_string())
        };
        return Err(CliError::flag(flag, format!("too coarse: the table, {} points over {} counts, would be {err:.3} mm off the plan (at most {TABLE_REFUSED_MM} mm): {fix}", t.points.len(), t.period_counts)));
    }
    Ok((t, err))
}

/// The lathe speed the X axis allows, in a refusal: below the 1 rpm
/// floor, that the axis is at fault.
fn allows(max_rpm: Option<f64>) -> String {
    match max_rpm {
        Some(r) if r < 1.0 => "this X axis cannot follow even at 1 rpm: give it more speed and acceleration".into(),
        Some(r) => format!("at most {} rpm", floor_tenth(r)),
        None => "at any lathe speed".into(),
    }
}

/// The lathe speed the X axis allows, or that it sets no limit.
fn up_to(max_rpm: Option<f64>) -> String {
    match max_rpm {
        Some(r) => format!("up to {} rpm", floor_tenth(r)),
        None => "any lathe speed: the X axis does not move".into(),
    }
}

#[cfg(test)]
#[path = "compensate_tests.rs"]
mod tests;
