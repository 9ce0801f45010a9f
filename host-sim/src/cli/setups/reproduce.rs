//! The command lines that reproduce a row: a machinist's next
//! steps are `geometry` to see the section and `simulate` to prove it.
//! Each line is checked as the CLI would take it, so a line that would be
//! refused is never printed as if it would run.

use super::SetupsArgs;
use crate::cli::errors::{adapt, Parsed};
use crate::cli::{command, simulate, Cli, Command};
use crate::planner::Candidate;
use clap::FromArgMatches;

/// The lathe speed the simulate line takes when `setups` had no --rpm:
/// the manual's own simulate example.
pub const EXAMPLE_RPM: f64 = 300.0;

/// Lathe turns the simulate line cuts per turn of the pattern: enough for
/// every flat to be cut several times over.
const TURNS_PER_PATTERN: u32 = 10;

pub struct Lines {
    pub geometry: String,
    pub simulate: String,
    /// a warning for a line the CLI would refuse as printed
    pub refused: Vec<String>,
}

/// The `geometry` and `simulate` lines for candidate `c` with cutter `r1`,
/// the stock and the cut as they were given.
pub fn lines(a: &SetupsArgs, r1: f64, c: &Candidate) -> Lines {
    let setup = format!(
        "--cutter-radius {r1} {} {} --ratio {} --edges {} --direction {}",
        a.stock.as_given(),
        a.cut.as_given(),
        c.ratio,
        c.edges,
        c.direction
    );
    let rpm = a.rpm.unwrap_or(EXAMPLE_RPM);
    let geometry = format!("polyturn geometry {setup}");
    let simulate = format!("polyturn simulate {setup} --rpm {rpm} --revolutions {}", TURNS_PER_PATTERN * c.revolutions);
    let refused = check(&simulate).err();
    Lines { geometry, simulate, refused: refused.into_iter().collect() }
}

/// The simulate line through the CLI's own parser and checks (not the
/// run): the setup as `geometry` checks it, then the speed, turns and
/// motor. The lines share the setup, so a refused setup refuses both.
fn check(line: &str) -> Result<(), String> {
    let parsed = command().try_get_matches_from(line.split(' ')).and_then(|m| Cli::from_arg_matches(&m));
    let refused = |e: String| format!("the simulate line is refused as printed: {e}");
    let s = match adapt(parsed).map_err(|e| refused(e.0))? {
        Parsed::Run(Cli { command: Command::Simulate(s) }) => s,
        _ => return Err("not a simulate line".into()),
    };
    s.setup.setup().map_err(|e| format!("both lines are refused as printed: {}", e.0))?;
    simulate::scenario_from(&s).map(|_| ()).map_err(|e| refused(e.0))
}
