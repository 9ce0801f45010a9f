//! `polyturn sequence`: the order in which a single-point tool cuts the
//! sides of a sharp-cornered polygon (the noncircular turning note, Theorem 2).

use super::errors::{CliError, CliResult};
use super::values::whole32;
use crate::noncircular::{check, order, smallest_m};
use serde_json::json;

#[derive(clap::Args, Debug)]
pub struct SequenceArgs {
    /// Sides N of the polygon
    #[arg(long, value_name = "N", value_parser = whole32(3, 10_000))]
    pub sides: u32,
    /// Lathe turns per pattern m: >= 2, coprime with --sides, not 1 more than a multiple of it (the noncircular turning note, Theorem 2) [default: the smallest]
    #[arg(long, value_name = "M", value_parser = whole32(2, 1_000_000))]
    pub m: Option<u32>,
    /// Print the order as JSON
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: SequenceArgs) -> CliResult<String> {
    let n = a.sides;
    let m = match a.m {
        Some(m) => {
            check(n, m).map_err(|e| CliError::flag("m", e.describe()))?;
            m
        }
        None => smallest_m(n).map_err(|e| CliError::flag("sides", e.describe()))?,
    };
    let o = order(n, m);
    if a.json {
        return Ok(json!({"m": m, "order": o, "revolutions": m}).to_string());
    }
    let seq: Vec<String> = o.iter().map(u32::to_string).collect();
    Ok(format!("{n} sides in {m} revolutions, m = {m}: {}", seq.join("-")))
}
