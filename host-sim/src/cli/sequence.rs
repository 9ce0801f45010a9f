//! `polyturn sequence`: the order in which a single-point tool cuts the
//! sides of a sharp-cornered polygon (seed 004, Theorem 2).

use super::args::{Args, CliError, CliResult};
use crate::noncircular::{check, order, smallest_m};
use serde_json::json;

pub const USAGE: &str = "polyturn sequence --sides N [--m M] [--json]";

pub fn run(argv: &[String]) -> CliResult<String> {
    let a = Args::parse(argv, &["sides", "m"], &["json"])?;
    a.required("sides")?;
    let n = a.whole("sides", 3, 10_000)?.unwrap_or(0) as u32;
    let m = match a.whole("m", 0, 1_000_000)? {
        Some(m) => {
            let m = m as u32;
            check(n, m).map_err(|e| CliError::flag("m", e.describe()))?;
            m
        }
        None => smallest_m(n).map_err(|e| CliError::flag("sides", e.describe()))?,
    };
    let o = order(n, m);
    if a.has("json") {
        return Ok(json!({"m": m, "order": o, "revolutions": m}).to_string());
    }
    let seq: Vec<String> = o.iter().map(u32::to_string).collect();
    Ok(format!("{n} sides in {m} revolutions, m = {m}: {}", seq.join("-")))
}
