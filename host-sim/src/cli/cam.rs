//! `polyturn cam`: smooth single-point tool paths for a sharp-cornered
//! polygon (the noncircular turning note), checked against the X axis, and the cam table.

mod request;

use super::errors::{CliError, CliResult};
use super::limits::{floor_tenth, past};
use super::output::Outputs;
use super::values::{out_file, rpm, whole32, within};
use super::x_table::{board_takes, TableArgs};
use crate::geometry::svg::Drawing;
use crate::noncircular::order;
use crate::noncircular::path::ToolPath;
use crate::noncircular::plan::{plan, Evaluation, Limit, Outcome, TOLERANCE_MM};
use crate::noncircular::rounded::Rounded;
use crate::noncircular::table::{build, CamFile};
use request::{request, turns, Request};
use serde_json::json;
use std::f64::consts::TAU;
use std::path::PathBuf;

/// A table further than this from its own tool path cuts another part:
/// refused (more steps per mm or encoder counts fix it).
pub const TABLE_REFUSED_MM: f64 = 0.1;
/// Past this the report calls the table coarse.
pub const TABLE_COARSE_MM: f64 = 0.01;

/// Sides N at most.
const MAX_SIDES: u32 = 360;

// Numbers take a leading '-' as a value (`--rpm -inf`), so that it is
// refused naming its flag rather than read as flags `-i -n -f`.
#[derive(clap::Args, Debug)]
pub struct CamArgs {
    /// Sides N of the sharp polygon
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = whole32(3, MAX_SIDES))]
    pub sides: u32,
    /// Inscribed radius (half the across-flats), mm
    #[arg(long, value_name = "MM", allow_hyphen_values = true, value_parser = within(0.001, 500.0, "mm"))]
    pub inscribed_radius: f64,
    /// Lathe speed while cutting, rpm
    #[arg(long, value_name = "RPM", allow_hyphen_values = true, value_parser = rpm(3000.0))]
    pub rpm: f64,
    /// The X axis's top speed, mm/s; at most 10000 steps/s with --steps-per-mm
    #[arg(long, value_name = "MM/S", allow_hyphen_values = true, value_parser = within(0.001, 1e4, "mm/s"))]
    pub x_max_speed: f64,
    /// The X axis's top acceleration, mm/s^2
    #[arg(long, value_name = "MM/S^2", allow_hyphen_values = true, value_parser = within(0.001, 1e6, "mm/s^2"))]
    pub x_max_accel: f64,
    /// Lathe turns per pattern m: 2..=N-1 and at most 128, co-prime with N (the noncircular turning note's Theorem 2). The cuts set the top speed, not m: m + N cuts the sides in the same order in N more turns, and past 128 a cut gets under 8 of the table's 1024 points [default: the smallest valid]
    #[arg(long, value_name = "M", allow_hyphen_values = true, value_parser = turns)]
    pub m: Option<u32>,
    #[command(flatten)]
    pub board: TableArgs,
    /// Also draw the tool path and the section to this SVG file (- for stdout)
    #[arg(long, value_name = "FILE", value_parser = out_file)]
    pub svg: Option<PathBuf>,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: CamArgs) -> CliResult<String> {
    let r = request(&a)?;
    let (path, e, corners, sharp_rpm): (Box<dyn ToolPath>, Evaluation, Corners, f64) =
        match plan(r.polygon, r.m, r.axis) {
            Outcome::Sharp(p, e) => {
                let rpm = e.max_rpm;
                (Box::new(p), e, Corners::Sharp { m: r.m }, rpm)
            }
            // an m asked for is a pattern of sharp corners: not swapped
            // for one rounded turn behind the machinist's back
            Outcome::Rounded(_, _, sharp) if a.m.is_some() => return Err(sharp_refused(&r, sharp)),
            Outcome::Rounded(f, e, sharp) if e.max_rpm >= r.axis.rpm => (Box::new(f), e, Corners::Rounded(f), sharp),
            Outcome::Rounded(_, e, _) => return Err(refusal(&e, &r)),
        };
    let table = build(path.as_ref(), r.counts_per_rev, r.steps_per_mm, r.rates);
    let table_dev = table.deviation(path.as_ref(), 8192);
    faithful(&table, table_dev, &r)?;
    let mut files = Outputs::default();
    if let Some(file) = &a.board.table {
        files.add("table", file, serde_json::to_string(&table).map_err(|e| CliError(e.to_string()))?)?;
    }
    if let Some(file) = &a.svg {
        files.add("svg", file, drawing(path.as_ref(), &e, &table))?;
    }
    let written = files.write()?;
    let report = report(&e, &r, corners, &table, table_dev, sharp_rpm);
    let out = match (a.json, written.wrote()) {
        (true, _) => report.to_string(),
        (false, None) => text(&report),
        (false, Some(w)) => format!("{}\n{w}", text(&report)),
    };
    Ok(written.report(out))
}

/// The table must be one the firmware takes (the sync core's own checks,
/// `check_table`) and must cut the path it was made from: refused, naming
/// the flag that would fix it, when it is further off than TABLE_REFUSED_MM.
fn faithful(table: &CamFile, dev_mm: f64, r: &Request) -> CliResult<()> {
    board_takes(table)?;
    if dev_mm <= TABLE_REFUSED_MM {
        return Ok(());
    }
    // Whole X steps put up to half a step of error in every point.
    let half_step = 0.5 / r.steps_per_mm;
    if half_step * 2.0 > TABLE_REFUSED_MM {
        return Err(CliError::flag("steps-per-mm", format!("must be >= {:.0} steps/mm: the table would cut {dev_mm:.3} mm off its tool path (at most {TABLE_REFUSED_MM} mm)", 1.0 / TABLE_REFUSED_MM)));
    }
    Err(CliError::flag("encoder-cpr", format!("too coarse: the table, {} points over {} counts, would cut {dev_mm:.3} mm off its tool path (at most {TABLE_REFUSED_MM} mm)", table.points.len(), table.period_counts)))
}

/// What the corners will be.
#[derive(Clone, Copy)]
enum Corners {
    Sharp { m: u32 },
    Rounded(Rounded),
}

fn report(
    e: &Evaluation,
    r: &Request,
    corners: Corners,
    table: &CamFile,
    table_dev: f64,
    sharp_rpm: f64,
) -> serde_json::Value {
    let um = |mm: f64| (mm * 1e4).round() / 10.0;
    let n = r.polygon.sides;
    // a fillet on a convex corner cuts the corner back (less material)
    let (kind, m, fillet, rounding) = match corners {
        Corners::Sharp { m } => ("sharp", m, None, e.excess),
        Corners::Rounded(f) => ("rounded", 1, Some(f.radius_mm), f.shortfall()),
    };
    let path_dev = e.excess.max(e.overcut);
    // A valid but poor result is said plainly, in both outputs.
    let mut warnings: Vec<String> = Vec::new();
    if let Some(f) = fillet.filter(|f| *f > 0.1 * r.polygon.apothem_mm) {
        let cure = if sharp_rpm >= 1.0 {
            format!("lower --rpm to {} or give the X axis more speed and acceleration", floor_tenth(sharp_rpm))
        } else {
            "give the X axis more speed and acceleration (even 1 rpm is too fast for them)".into()
        };
        warnings.push(format!("the corner fillets ({f:.3} mm) exceed a tenth of the inscribed radius: this is a rounded polygon; for sharp corners {cure}"));
    }
    if table_dev > TABLE_COARSE_MM {
        warnings.push(format!(
            "the table cuts {:.1} µm off its tool path: raise --steps-per-mm or --encoder-cpr for a finer one",
            table_dev * 1e3
        ));
    }
    json!({
        "warnings": warnings,
        "sides": n,
        "m": m,
        "order": if m > 1 { order(n, m) } else { (0..n).collect() },
        "revolutions": m,
        "corners": kind,
        "corner_fillet_mm": fillet,
        "corner_rounding_um": um(rounding),
        "path_deviation_um": um(path_dev),
        "table_deviation_um": um(table_dev),
        "within_1um": kind == "sharp" && path_dev + table_dev <= TOLERANCE_MM,
        "x_min_mm": e.travel.0,
        "x_max_mm": e.travel.1,
        "x_travel_mm": e.travel.1 - e.travel.0,
        "peak_x_speed": e.peak_speed,
        "peak_x_accel": e.peak_accel,
        "velocity_jump_mm_s": e.velocity_jump,
        "max_rpm": e.max_rpm,
        "sharp_max_rpm": sharp_rpm,
        "limited_by": e.limit,
        "table": {"points": table.points.len(), "period_counts": table.period_counts, "counts_per_rev": table.counts_per_rev},
    })
}

fn text(j: &serde_json::Value) -> String {
    let warnings: String = j["warnings"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|w| w.as_str())
        .map(|w| format!("\nwarning: {w}"))
        .collect();
    body(j) + &warnings
}

fn body(j: &serde_json::Value) -> String {
    let f = |k: &str| j[k].as_f64().unwrap_or(0.0);
    let order: Vec<String> = j["order"].as_array().into_iter().flatten().map(|v| v.to_string()).collect();
    let corners = match j["corners"].as_str() {
        Some("sharp") => format!("sharp, {:.1} µm from the polygon", f("path_deviation_um")),
        _ => format!(
            "rounded to {:.3} mm fillets (corners {:.1} µm inside the sharp ones; sharp needs <= {} rpm)",
            f("corner_fillet_mm"),
            f("corner_rounding_um"),
            floor_tenth(f("sharp_max_rpm"))
        ),
    };
    format!(
        "{} sides in {} revolution(s), order {}\ncorners {corners}; the table as the core cuts it adds {:.1} µm\nX from {:.3} to {:.3} mm, peak {:.1} mm/s, {:.0} mm/s^2; velocity continuous (largest jump {:.1e} mm/s)\nup to {:.1} rpm ({} limit); table {} points over {} lathe counts",
        j["sides"], j["m"], order.join("-"), f("table_deviation_um"), f("x_min_mm"), f("x_max_mm"), f("peak_x_speed"),
        f("peak_x_accel"), f("velocity_jump_mm_s"), f("max_rpm"), j["limited_by"].as_str().unwrap_or(""),
        j["table"]["points"], j["table"]["period_counts"]
    )
}

/// Why the sharp corners of `--m` cannot be cut at `--rpm`.
fn sharp_refused(r: &Request, sharp_rpm: f64) -> CliError {
    let m = r.m;
    if sharp_rpm >= 1.0 {
        CliError::flag(
            "rpm",
            format!(
                "must be <= {} rpm for sharp corners with --m {m}: the X axis cannot follow them faster (without --m the table cuts rounded corners in one turn) (got {})",
                floor_tenth(sharp_rpm),
                r.axis.rpm
            ),
        )
    } else {
        CliError::flag(
            "m",
            format!("{m} asks for sharp corners the X axis cannot follow even at 1 rpm: give it more speed and acceleration, or leave --m out for rounded corners in one turn"),
        )
    }
}

/// No corner rounding fits the axis at `--rpm`: the speed that one does
/// (rounded down: a named bound is taken), or, below 1 rpm, the axis's
/// limit that binds, with what it needs at 1 rpm.
fn refusal(e: &Evaluation, r: &Request) -> CliError {
    // X speed goes with the lathe speed, X acceleration with its square
    let at = if e.max_rpm < 1.0 { 1.0 } else { r.axis.rpm };
    let scale = at / r.axis.rpm;
    let (flag, which) = match e.limit {
        Limit::Speed => {
            let need = past(e.peak_speed * scale, r.axis.max_speed, 1);
            ("x-max-speed", format!("X speed {need} mm/s > {} mm/s", r.axis.max_speed))
        }
        Limit::Accel => {
            let need = past(e.peak_accel * scale * scale, r.axis.max_accel, 0);
            ("x-max-accel", format!("X acceleration {need} mm/s^2 > {} mm/s^2", r.axis.max_accel))
        }
    };
    // Too slow even for the slowest lathe speed taken: the axis is at fault.
    if e.max_rpm < 1.0 {
        return CliError::flag(flag, format!("is too low: even a nearly round section at 1 rpm needs {which}"));
    }
    CliError::flag(
        "rpm",
        format!(
            "must be <= {} rpm for this X axis: even a nearly round section needs {which} (got {})",
            floor_tenth(e.max_rpm),
            r.axis.rpm
        ),
    )
}

/// The tool loops (grey), the section the table cuts (filled) and the
/// sharp polygon (red).
fn drawing(path: &dyn ToolPath, e: &Evaluation, table: &CamFile) -> String {
    let (poly, m) = (path.polygon(), path.revolutions());
    let mut d = Drawing::new(e.travel.1 * 1.1, 560.0);
    let polar = |phi: f64, r: f64| (r * phi.cos(), r * phi.sin());
    let k = 720 * m as usize;
    let loops: Vec<_> = (0..k).map(|i| TAU * m as f64 * i as f64 / k as f64).map(|p| polar(p, path.at(p)[0])).collect();
    d.path(&loops, true, r##"fill="none" stroke="#999" stroke-width="0.8""##);
    let cut = |p: f64| (0..m).map(|j| table.radius(poly.apothem_mm, p + TAU * j as f64)).fold(f64::INFINITY, f64::min);
    let section: Vec<_> = (0..2048).map(|i| TAU * i as f64 / 2048.0).map(|p| polar(p, cut(p))).collect();
    d.path(&section, true, r##"fill="#3569" stroke="#124" stroke-width="1.5""##);
    let corners = (0..poly.sides).map(|j| (j as f64 + 0.5) * TAU / poly.sides as f64);
    let ideal: Vec<_> = corners.map(|p| polar(p, poly.radius(p))).collect();
    d.path(&ideal, true, r##"fill="none" stroke="#c33" stroke-width="0.8""##);
    // two lines: on one, 10 sides or more ran past the drawing's edge
    let turns = if m == 1 { "1 lathe turn".to_string() } else { format!("{m} lathe turns") };
    d.text(0, &format!("{} sides in {turns}", poly.sides));
    d.text(1, "tool path (grey), section (blue), polygon (red)");
    d.finish(560.0)
}

#[cfg(test)]
#[path = "cam_tests.rs"]
mod tests;
