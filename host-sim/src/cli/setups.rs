//! `polyturn setups`: which setups cut the polygon you want, what it
//! assumed, what to run next and what to beware of.

mod advice;
#[cfg(test)]
mod advice_tests;
mod assumed;
#[cfg(test)]
mod geometry_tests;
mod reproduce;
mod table;
#[cfg(test)]
mod tests;

use super::errors::{CliError, CliResult};
use super::measure::{Cut, Stock};
use super::values::{length_mm, ratio_bound, rpm, setting, whole32, within};
use crate::geometry::LENGTH_MM;
use crate::planner::{plan, Request};
use advice::Limits;
use assumed::Cutter;
use polyturn_sync::config::table::EDGES;
use table::Report;

#[derive(clap::Args, Debug)]
pub struct SetupsArgs {
    /// Sides N of the polygon wanted
    #[arg(long, value_name = "N", value_parser = whole32(2, 1000))]
    pub sides: u32,
    #[command(flatten)]
    pub stock: Stock,
    #[command(flatten)]
    pub cut: Cut,
    /// Cutter radius R1, mm [default: 5 x the stock radius, said in the output]
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub cutter_radius: Option<f64>,
    /// Most cutting edges Z to consider
    #[arg(long, value_name = "Z", default_value = "6", value_parser = setting(EDGES))]
    pub max_edges: u32,
    /// Largest gear ratio to consider: 8, 8:1, 15/2 or 7.5
    #[arg(long, value_name = "GR", default_value = "8", value_parser = ratio_bound(0.01, 1000.0))]
    pub max_ratio: f64,
    /// Most lathe turns per pattern to consider
    #[arg(long, value_name = "TURNS", default_value = "1", value_parser = whole32(1, 12))]
    pub max_revolutions: u32,
    /// Lathe speed, rpm: adds the cutter's speed and tip speed
    #[arg(long, value_name = "RPM", value_parser = rpm(10_000.0))]
    pub rpm: Option<f64>,
    /// Flat deviation to size the smallest cutter for, mm
    #[arg(long, value_name = "MM", default_value = "0.01", value_parser = within(0.0001, 10.0, "mm"))]
    pub tolerance: f64,
    /// Warn of setups whose cutter tip, with --rpm, cuts faster than this, m/s
    #[arg(long, value_name = "M/S", default_value_t = advice::DEFAULT_MAX_TIP_SPEED, value_parser = within(0.01, 1000.0, "m/s"))]
    pub max_tip_speed: f64,
    /// Warn of setups that, with --rpm, turn the cutter faster than this, rpm; the default is the firmware's default motor's top speed, 200000 steps/s at 3200 steps a turn
    #[arg(long, value_name = "RPM", default_value_t = advice::default_max_cutter_rpm(), value_parser = within(1.0, 1e6, "rpm"))]
    pub max_cutter_rpm: f64,
    /// Print the setups as JSON
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: SetupsArgs) -> CliResult<String> {
    let req = request(&a)?;
    let crate::planner::Plan { found, round, refused } = plan(&req);
    let limits = Limits { tip_speed: a.max_tip_speed, cutter_rpm: a.max_cutter_rpm };
    let cutter = Cutter::of(&req);
    let lines = found.first().map(|c| reproduce::lines(&a, cutter.radius, c));
    let mut warnings = advice::warnings(&found, &req, &limits);
    // a line that would be refused as printed is said so, with the reason
    warnings.extend(lines.iter().flat_map(|l| l.refused.clone()));
    let mut notes = assumed::notes(&found, &req);
    if round > 0 {
        notes.push(format!(
            "{round} more left out: with this cutter their section is nearly round, and geometry refuses them (a larger --cutter-radius gives flatter sides)"
        ));
    }
    notes.extend(refused.iter().map(|(e, n)| cutter.left_out(*n, e)));
    let r = Report { req: &req, found: &found, cutter, lines, limits, notes, warnings };
    Ok(if a.json { r.json().to_string() } else { r.human() })
}

/// The planner's request, each flag checked against the others.
fn request(a: &SetupsArgs) -> CliResult<Request> {
    let r2 = a.stock.radius_for_a_cut()?;
    let depth = a.cut.depth(r2)?;
    assumed_cutter_fits(a.cutter_radius, r2)?;
    if let Some(r1) = a.cutter_radius.filter(|&r1| r1 <= depth) {
        return Err(CliError::flag(
            "cutter-radius",
            format!("must be > the depth ({depth} mm): {r1} mm puts the cutter's axis inside the bar"),
        ));
    }
    Ok(Request {
        sides: a.sides,
        stock_radius: r2,
        depth,
        cutter_radius: a.cutter_radius,
        max_edges: a.max_edges,
        max_ratio: a.max_ratio,
        max_revolutions: a.max_revolutions,
        rpm: a.rpm,
        tolerance: a.tolerance,
    })
}

/// Without --cutter-radius, the assumed cutter (5 x the stock radius) must
/// be one `geometry` takes: past its lengths every setup would be left
/// out, and a table of none would read as no setup cutting the polygon.
fn assumed_cutter_fits(given: Option<f64>, stock_radius: f64) -> CliResult<()> {
    let (lo, hi) = LENGTH_MM;
    let assumed = crate::planner::default_cutter(stock_radius);
    if given.is_some() || (lo..=hi).contains(&assumed) {
        return Ok(());
    }
    Err(CliError::flag(
        "cutter-radius",
        format!(
            "must be given for a stock radius over {} mm (got none): the cutter assumed without it, 5 x the stock radius {stock_radius} mm, is {assumed} mm, past geometry's {lo}..={hi} mm",
            hi / 5.0
        ),
    ))
}
