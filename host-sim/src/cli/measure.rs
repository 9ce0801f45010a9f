//! The stock and the cut as a machinist measures them: calipers
//! read diameters and across-flats, so the stock is given by its radius or
//! its diameter, and the cut by its depth or the across-flats wanted,
//! exactly one of each. `geometry`, `simulate`, `compensate` and `setups`
//! share these flags and this arithmetic.

use super::errors::{CliError, CliResult};
use super::values::{length_mm, within, LENGTH_MM};
use crate::geometry::SectionSummary;

/// The stock before the cut: one of its radius or its diameter.
#[derive(clap::Args, Debug, Clone)]
#[group(required = true, multiple = false)]
pub struct Stock {
    /// Stock radius R2 before the cut, mm; or give --stock-diameter
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub stock_radius: Option<f64>,
    /// Stock diameter before the cut, mm; or give --stock-radius
    #[arg(long, value_name = "MM", value_parser = within(0.001, 20_000.0, "mm"))]
    pub stock_diameter: Option<f64>,
}

impl Stock {
    /// R2, mm. clap's group makes exactly one present; the refusal here
    /// keeps that true for a `Stock` built any other way.
    pub fn radius(&self) -> CliResult<f64> {
        match (self.stock_radius, self.stock_diameter) {
            (Some(r), None) => Ok(r),
            (None, Some(d)) => Ok(d / 2.0),
            _ => Err(CliError::flag("stock-radius", "or --stock-diameter: give exactly one of them")),
        }
    }

    /// R2, mm, refused naming the flag given where it is too thin for any
    /// cut: a depth of at least a micron (the least `--depth` takes) that
    /// leaves some stock needs R2 over a micron.
    pub fn radius_for_a_cut(&self) -> CliResult<f64> {
        let r2 = self.radius()?;
        if r2 > LENGTH_MM.0 {
            return Ok(r2);
        }
        let (flag, least, got) = match self.stock_radius {
            Some(r) => ("stock-radius", LENGTH_MM.0, r),
            None => ("stock-diameter", 2.0 * LENGTH_MM.0, 2.0 * r2),
        };
        Err(CliError::flag(
            flag,
            format!(
                "must be more than {least} mm for any cut: a depth of cut of at least {} mm that leaves some stock (got {got})",
                LENGTH_MM.0
            ),
        ))
    }

    /// The flag as it was given, to write a command line back.
    pub fn as_given(&self) -> String {
        match (self.stock_radius, self.stock_diameter) {
            (None, Some(d)) => format!("--stock-diameter {d}"),
            (r, _) => format!("--stock-radius {}", r.unwrap_or(0.0)),
        }
    }
}

/// How deep to cut: the depth at the flats' middle, or the across-flats
/// wanted (twice the inscribed radius).
#[derive(clap::Args, Debug, Clone)]
#[group(required = true, multiple = false)]
pub struct Cut {
    /// Depth of cut DOC at the flats' middle, mm, less than the stock radius; or give --across-flats
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub depth: Option<f64>,
    /// Across flats wanted, mm: twice the inscribed radius (< the stock diameter); or give --depth
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub across_flats: Option<f64>,
}

impl Cut {
    /// DOC for stock radius `r2`: the flats' middle is the inscribed
    /// radius, R2 - DOC, so across flats AF is 2 (R2 - DOC).
    pub fn depth(&self, r2: f64) -> CliResult<f64> {
        match (self.across_flats, self.depth) {
            // the depth it leaves is one --depth would take: at least a
            // micron (to the float's rounding: 20 - 19.998 is not 0.002)
            (Some(af), None) if r2 - af / 2.0 >= LENGTH_MM.0 * (1.0 - 1e-9) => Ok((r2 - af / 2.0).max(LENGTH_MM.0)),
            (Some(af), None) => Err(CliError::flag(
                "across-flats",
                format!(
                    "must be at most the stock diameter ({} mm) less {} mm: a depth of cut of at least {} mm (got '{af}')",
                    2.0 * r2,
                    2.0 * LENGTH_MM.0,
                    LENGTH_MM.0
                ),
            )),
            (None, Some(d)) if d < r2 => Ok(d),
            (None, Some(d)) => {
                Err(CliError::flag("depth", format!("must be > 0 and < the stock radius ({r2} mm) (got {d})")))
            }
            _ => Err(CliError("give exactly one of --across-flats AF or --depth DOC".into())),
        }
    }

    /// The flag as it was given, to write a command line back.
    pub fn as_given(&self) -> String {
        match (self.depth, self.across_flats) {
            (None, Some(af)) => format!("--across-flats {af}"),
            (d, _) => format!("--depth {}", d.unwrap_or(0.0)),
        }
    }
}

/// Across corners, mm: the circumscribed diameter where corners face
/// corners (even sides); None for odd sides, where a corner faces a flat.
pub fn across_corners(s: &SectionSummary) -> Option<f64> {
    s.across_flats.map(|_| 2.0 * s.circumscribed_radius)
}

/// What calipers read on the section: across flats and across corners,
/// or, with odd sides, from a corner to the flat facing it.
pub fn calipers(s: &SectionSummary) -> String {
    match (s.across_flats, across_corners(s)) {
        (Some(af), Some(ac)) => format!("across flats {af:.4} mm, across corners {ac:.4} mm"),
        _ => format!(
            "across flats n/a (odd sides), corner to opposite flat {:.4} mm",
            s.inscribed_radius + s.circumscribed_radius
        ),
    }
}

#[cfg(test)]
mod tests;
