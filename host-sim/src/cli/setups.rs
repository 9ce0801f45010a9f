//! `polyturn setups`: which setups cut the polygon you want.

use super::args::{Args, CliError, CliResult};
use crate::planner::{default_cutter, plan, Request};

pub const USAGE: &str = "polyturn setups --sides N --stock-radius R2 (--across-flats AF | --depth DOC) [--cutter-radius R1] [--max-edges 6] [--max-ratio 8] [--max-revolutions 1] [--rpm RPM] [--tolerance 0.01] [--json]";
const VALUED: &[&str] = &[
    "sides",
    "stock-radius",
    "across-flats",
    "depth",
    "cutter-radius",
    "max-edges",
    "max-ratio",
    "max-revolutions",
    "rpm",
    "tolerance",
];

pub fn run(argv: &[String]) -> CliResult<String> {
    let a = Args::parse(argv, VALUED, &["json"])?;
    a.required("sides")?;
    let sides = a.whole("sides", 2, 1000)?.unwrap_or(6) as u32;
    let r2 = a.required_length_mm("stock-radius")?;
    let depth = match (a.length_mm("across-flats")?, a.length_mm("depth")?) {
        (Some(af), None) if af < 2.0 * r2 => r2 - af / 2.0,
        (Some(_), None) => {
            return Err(CliError::flag("across-flats", format!("must be < the stock diameter ({} mm)", 2.0 * r2)))
        }
        (None, Some(d)) if d < r2 => d,
        (None, Some(_)) => {
            return Err(CliError::flag("depth", format!("must be > 0 and < the stock radius ({r2} mm)")))
        }
        _ => return Err(CliError("give exactly one of --across-flats AF or --depth DOC".into())),
    };
    let req = Request {
        sides,
        stock_radius: r2,
        depth,
        cutter_radius: a.length_mm("cutter-radius")?,
        max_edges: a.whole("max-edges", 1, 12)?.unwrap_or(6) as u32,
        max_ratio: a.number("max-ratio", 0.0, 1000.0, true, "")?.unwrap_or(8.0),
        max_revolutions: a.whole("max-revolutions", 1, 12)?.unwrap_or(1) as u32,
        rpm: a.number("rpm", 0.0, 10_000.0, true, "rpm")?,
        tolerance: a.number("tolerance", 0.0, 10.0, true, "mm")?.unwrap_or(0.01),
    };
    let found = plan(&req);
    if a.has("json") {
        return Ok(serde_json::json!({"sides": sides, "depth": depth, "setups": found}).to_string());
    }
    if found.is_empty() {
        return Ok(format!(
            "no setup cuts {sides} sides within --max-edges {} and --max-ratio {}",
            req.max_edges, req.max_ratio
        ));
    }
    let r1 = req.cutter_radius.unwrap_or_else(|| default_cutter(r2));
    let mut s = format!(
        "{} setups for {sides} sides, depth {depth:.3} mm, cutter radius {r1} mm (flattest first):\n",
        found.len()
    );
    s += "ratio  edges dir       turns  flat dev mm  corners  cutter rpm  tip m/s  min R1 mm\n";
    for c in &found {
        let opt = |v: Option<f64>, p: usize| v.map(|x| format!("{x:.p$}")).unwrap_or_else(|| "-".into());
        s += &format!(
            "{:<6} {:<5} {:<9} {:<6} {:>+11.4}  {:<7}  {:>10}  {:>7}  {:>9}\n",
            c.ratio,
            c.edges,
            c.direction,
            c.revolutions,
            c.flat_deviation,
            if c.corners_sharp { "sharp" } else { "round" },
            opt(c.cutter_rpm, 0),
            opt(c.peak_tip_speed, 2),
            opt(c.min_cutter_radius, 1)
        );
    }
    Ok(s.trim_end().to_string())
}
