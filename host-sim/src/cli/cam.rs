//! `polyturn cam`: smooth single-point tool paths for a sharp-cornered
//! polygon (seed 004), checked against the X axis, and the cam table.

use super::args::{Args, CliError, CliResult};
use crate::geometry::svg::Drawing;
use crate::noncircular::path::{Polygon, ToolPath};
use crate::noncircular::plan::{plan, Axis, Evaluation, Limit, Outcome, TOLERANCE_MM};
use crate::noncircular::rounded::Rounded;
use crate::noncircular::table::{build, CamFile};
use crate::noncircular::{check, order, smallest_m};
use serde_json::json;
use std::f64::consts::TAU;

pub const USAGE: &str = "polyturn cam --sides N --inscribed-radius R --rpm RPM --x-max-speed V(mm/s) --x-max-accel A(mm/s^2) [--m M] [--steps-per-mm S] [--encoder-counts C] [--table FILE] [--svg FILE] [--json]";
const VALUED: &[&str] = &[
    "sides",
    "inscribed-radius",
    "rpm",
    "x-max-speed",
    "x-max-accel",
    "m",
    "steps-per-mm",
    "encoder-counts",
    "table",
    "svg",
];
/// The firmware emits at most one X step per two control ticks (25 kHz).
pub const X_MAX_RATE_HZ: f64 = 12_500.0;

struct Request {
    polygon: Polygon,
    m: u32,
    axis: Axis,
    steps_per_mm: f64,
    counts_per_rev: u32,
}

fn request(a: &Args) -> CliResult<Request> {
    a.required("sides")?;
    let sides = a.whole("sides", 3, 360)?.unwrap_or(3) as u32;
    let m = match a.whole("m", 0, 1_000)? {
        Some(m) => check(sides, m as u32).map(|_| m as u32).map_err(|e| CliError::flag("m", e.describe()))?,
        None => smallest_m(sides).map_err(|e| CliError::flag("sides", e.describe()))?,
    };
    let need = |f: &str, hi: f64, unit: &str| -> CliResult<f64> {
        a.number(f, 0.0, hi, true, unit)?.ok_or_else(|| CliError::flag(f, "is required"))
    };
    let apothem_mm = need("inscribed-radius", 1000.0, "mm")?;
    let axis = Axis {
        rpm: need("rpm", 3000.0, "rpm")?,
        max_speed: need("x-max-speed", 1e4, "mm/s")?,
        max_accel: need("x-max-accel", 1e6, "mm/s^2")?,
    };
    let steps_per_mm = a.number("steps-per-mm", 0.0, 1e5, true, "steps/mm")?.unwrap_or(800.0);
    let counts_per_rev = a.whole("encoder-counts", 4, 1 << 20)?.unwrap_or(2400) as u32;
    if axis.max_speed * steps_per_mm > X_MAX_RATE_HZ {
        let top = X_MAX_RATE_HZ / steps_per_mm;
        return Err(CliError::flag("x-max-speed", format!("must be <= {top:.1} mm/s: the firmware emits at most {X_MAX_RATE_HZ} X steps/s ({steps_per_mm} steps/mm)")));
    }
    Ok(Request { polygon: Polygon { sides, apothem_mm }, m, axis, steps_per_mm, counts_per_rev })
}

pub fn run(argv: &[String]) -> CliResult<String> {
    let a = Args::parse(argv, VALUED, &["json"])?;
    let r = request(&a)?;
    let (path, e, corners, sharp_rpm): (Box<dyn ToolPath>, Evaluation, Corners, f64) =
        match plan(r.polygon, r.m, r.axis) {
            Outcome::Sharp(p, e) => {
                let rpm = e.max_rpm;
                (Box::new(p), e, Corners::Sharp { m: r.m }, rpm)
            }
            Outcome::Rounded(f, e, sharp) if e.max_rpm >= r.axis.rpm => (Box::new(f), e, Corners::Rounded(f), sharp),
            Outcome::Rounded(_, e, _) => return Err(refusal(&e, &r)),
        };
    let rates = ((r.axis.max_speed * r.steps_per_mm) as u32, (r.axis.max_accel * r.steps_per_mm) as u32);
    let table = build(path.as_ref(), r.counts_per_rev, r.steps_per_mm, rates);
    let table_dev = table.deviation(path.as_ref(), 8192);
    if let Some(file) = a.raw("table") {
        let text = serde_json::to_string(&table).map_err(|e| CliError(e.to_string()))?;
        std::fs::write(file, text).map_err(|e| CliError::flag("table", format!("could not write '{file}': {e}")))?;
    }
    if let Some(file) = a.raw("svg") {
        std::fs::write(file, drawing(path.as_ref(), &e, &table))
            .map_err(|e| CliError::flag("svg", format!("could not write '{file}': {e}")))?;
    }
    let report = report(&e, &r, corners, &table, table_dev, sharp_rpm);
    if a.has("json") {
        return Ok(report.to_string());
    }
    Ok(text(&report))
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
    json!({
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
    let f = |k: &str| j[k].as_f64().unwrap_or(0.0);
    let order: Vec<String> = j["order"].as_array().into_iter().flatten().map(|v| v.to_string()).collect();
    let corners = match j["corners"].as_str() {
        Some("sharp") => format!("sharp, {:.1} um from the polygon", f("path_deviation_um")),
        _ => format!(
            "rounded to {:.3} mm fillets (corners {:.1} um inside the sharp ones; sharp needs <= {:.1} rpm)",
            f("corner_fillet_mm"),
            f("corner_rounding_um"),
            f("sharp_max_rpm")
        ),
    };
    format!(
        "{} sides in {} revolution(s), order {}\ncorners {corners}; the table as the core cuts it adds {:.1} um\nX from {:.3} to {:.3} mm, peak {:.1} mm/s, {:.0} mm/s^2; velocity continuous (largest jump {:.1e} mm/s)\nup to {:.1} rpm ({} limit); table {} points over {} lathe counts",
        j["sides"], j["m"], order.join("-"), f("table_deviation_um"), f("x_min_mm"), f("x_max_mm"), f("peak_x_speed"),
        f("peak_x_accel"), f("velocity_jump_mm_s"), f("max_rpm"), j["limited_by"].as_str().unwrap_or(""),
        j["table"]["points"], j["table"]["period_counts"]
    )
}

fn refusal(e: &Evaluation, r: &Request) -> CliError {
    let which = match e.limit {
        Limit::Speed => format!("X speed {:.1} mm/s > {} mm/s", e.peak_speed, r.axis.max_speed),
        Limit::Accel => format!("X acceleration {:.0} mm/s^2 > {} mm/s^2", e.peak_accel, r.axis.max_accel),
    };
    CliError::flag(
        "rpm",
        format!("must be <= {:.1} rpm for this X axis: even a nearly round section needs {which}", e.max_rpm),
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
    d.text(0, &format!("{} sides, {m} revolutions: tool path (grey), section (blue), polygon (red)", poly.sides));
    d.finish(560.0)
}
