//! The six variables of a setup as flags, shared by `geometry`,
//! `simulate` and `compensate`, and the check that they cut a polygon.

use super::errors::{CliError, CliResult};
use super::measure::{Cut, Stock};
use super::values::{direction, length_mm, ratio, setting};
use crate::geometry::{Direction, Refusal, Roundness, Section, Setup};
use polyturn_sync::config::table::EDGES;
use polyturn_sync::Ratio;

/// Foale's R1, R2, DOC, GR, Z and sense.
#[derive(clap::Args, Debug)]
pub struct SetupArgs {
    /// Cutter radius R1: the cutting edge's distance from the cutter's axis, mm, more than --depth
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub cutter_radius: f64,
    #[command(flatten)]
    pub stock: Stock,
    #[command(flatten)]
    pub cut: Cut,
    /// Gear ratio GR, cutter turns per lathe turn, greater than 0: 2, 2:1, 5/2, 11:3 or 2.5 (numerator and denominator 1..=1000, at most 6 decimal places)
    #[arg(long, value_name = "GR", value_parser = ratio)]
    pub ratio: Ratio,
    /// Cutting edges Z on the cutter
    #[arg(long, value_name = "Z", value_parser = setting(EDGES))]
    pub edges: u32,
    /// The cutter's sense against the lathe's: same or opposite (the console's `dir`)
    #[arg(long, value_name = "same|opposite", value_parser = direction)]
    pub direction: Direction,
}

impl SetupArgs {
    /// The setup, checked as a whole (the depth against the stock, the
    /// cutter against the depth, and that it cuts a polygon, not a circle).
    pub fn setup(&self) -> CliResult<Setup> {
        self.setup_and_section().map(|(setup, _)| setup)
    }

    /// `setup`, and the ideal section its roundness check computed.
    pub fn setup_and_section(&self) -> CliResult<(Setup, Section)> {
        let stock_radius_mm = self.stock.radius_for_a_cut()?;
        let setup = Setup {
            cutter_radius_mm: self.cutter_radius,
            stock_radius_mm,
            depth_mm: self.cut.depth(stock_radius_mm)?,
            ratio: self.ratio,
            edges: self.edges,
            direction: self.direction,
        };
        let round = match setup.check() {
            Ok(section) => return Ok((setup, section)),
            Err(Refusal::Setting(e)) => return Err(CliError::flag(e.field, e.allowed)),
            Err(Refusal::Round(round)) => round,
        };
        Err(match round_whatever_the_cutter(&setup) {
            true => round_error(
                "ratio",
                format!(
                    "cuts a nearly round section with {} edges with any cutter up to 100 x the stock radius",
                    setup.edges
                ),
                &round,
                "a larger ratio turns the cutter fast enough to cut flats",
            ),
            false => round_error(
                "cutter-radius",
                "is too small for this depth: the section is nearly round".into(),
                &round,
                "a larger cutter gives flatter sides",
            ),
        })
    }
}

/// Whether a cutter of 100 times the stock's radius (the largest `setups`
/// considers) would still cut a round section: then the ratio is at
/// fault, not the cutter (at 1/1000 the cutter barely turns, and its tip
/// shaves a circle).
fn round_whatever_the_cutter(setup: &Setup) -> bool {
    // (the setup passed `validate`, so this cutter exceeds its depth; it
    // may pass the longest --cutter-radius, being no flag's)
    let big = Setup { cutter_radius_mm: 100.0 * setup.stock_radius_mm, ..*setup };
    Roundness::of_setup(&big).0.is_round()
}

fn round_error(flag: &'static str, what: String, round: &Roundness, fix: &str) -> CliError {
    CliError::flag(flag, format!("{what} ({}); {fix}", round.says))
}
