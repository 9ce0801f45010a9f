//! `polyturn setups`: which setups cut the polygon you want.

use super::errors::{CliError, CliResult};
use super::values::{above, length_mm, rpm, whole32};
use crate::planner::{default_cutter, plan, Request};

#[derive(clap::Args, Debug)]
pub struct SetupsArgs {
    /// Sides N of the polygon wanted (2..=1000)
    #[arg(long, value_name = "N", value_parser = whole32(2, 1000))]
    pub sides: u32,
    /// Stock radius R2 before the cut, mm
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub stock_radius: f64,
    /// Across flats wanted, mm (< the stock diameter); or give --depth
    #[arg(long, value_name = "MM", value_parser = length_mm(), conflicts_with = "depth", required_unless_present = "depth")]
    pub across_flats: Option<f64>,
    /// Depth of cut at the flats' middle, mm (< --stock-radius); or give --across-flats
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub depth: Option<f64>,
    /// Cutter radius R1, mm [default: a cutter suited to the stock]
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub cutter_radius: Option<f64>,
    /// Most cutting edges Z to consider (1..=12)
    #[arg(long, value_name = "Z", default_value = "6", value_parser = whole32(1, 12))]
    pub max_edges: u32,
    /// Largest gear ratio to consider (> 0, <= 1000)
    #[arg(long, value_name = "GR", default_value = "8", value_parser = above(0.0, 1000.0, ""))]
    pub max_ratio: f64,
    /// Most lathe turns per pattern to consider (1..=12)
    #[arg(long, value_name = "TURNS", default_value = "1", value_parser = whole32(1, 12))]
    pub max_revolutions: u32,
    /// Lathe speed, rpm (1..=10000): adds the cutter's speed and tip speed
    #[arg(long, value_name = "RPM", value_parser = rpm(10_000.0))]
    pub rpm: Option<f64>,
    /// Flat deviation to size the smallest cutter for, mm (> 0, <= 10)
    #[arg(long, value_name = "MM", default_value = "0.01", value_parser = above(0.0, 10.0, "mm"))]
    pub tolerance: f64,
    /// Print the setups as JSON
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: SetupsArgs) -> CliResult<String> {
    let (sides, r2) = (a.sides, a.stock_radius);
    let depth = match (a.across_flats, a.depth) {
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
    if let Some(r1) = a.cutter_radius.filter(|&r1| r1 <= depth) {
        return Err(CliError::flag(
            "cutter-radius",
            format!("must be > the depth ({depth} mm): {r1} mm puts the cutter's axis inside the bar"),
        ));
    }
    let req = Request {
        sides,
        stock_radius: r2,
        depth,
        cutter_radius: a.cutter_radius,
        max_edges: a.max_edges,
        max_ratio: a.max_ratio,
        max_revolutions: a.max_revolutions,
        rpm: a.rpm,
        tolerance: a.tolerance,
    };
    let found = plan(&req);
    if a.json {
        let r1 = req.cutter_radius.unwrap_or_else(|| default_cutter(r2));
        return Ok(
            serde_json::json!({"sides": sides, "depth": depth, "cutter_radius": r1, "setups": found}).to_string()
        );
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
