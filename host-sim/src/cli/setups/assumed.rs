//! What the planner assumed, said: the cutter radius
//! the figures are for and why, and what each "-" in the table means.

use crate::geometry::SetupError;
use crate::planner::{default_cutter, min_cutter_scan_top, Candidate, Request};

/// The cutter radius the figures are for, and why that one.
pub struct Cutter {
    pub radius: f64,
    /// None when given with --cutter-radius; else why this radius
    pub assumed: Option<String>,
}

impl Cutter {
    pub fn of(req: &Request) -> Cutter {
        match req.cutter_radius {
            Some(radius) => Cutter { radius, assumed: None },
            None => Cutter {
                radius: default_cutter(req.stock_radius),
                assumed: Some(
                    "5 x the stock radius, the proportion of Foale's examples (a 50 mm cutter on 10 mm stock); give --cutter-radius for yours"
                        .into(),
                ),
            },
        }
    }

    /// The note for `n` setups left out for a value `geometry` refuses:
    /// the flag and its range, and, where the value is the assumed
    /// cutter's, that a cutter given is not assumed.
    pub fn left_out(&self, n: usize, e: &SetupError) -> String {
        let note = format!("{n} more left out: geometry refuses them: --{} {}", e.field, e.allowed);
        match (e.field, &self.assumed) {
            ("cutter-radius", Some(_)) => {
                format!("{note} (got the assumed {} mm, 5 x the stock radius): give --cutter-radius", self.radius)
            }
            _ => note,
        }
    }

    /// `cutter radius 50 mm (--cutter-radius)`, or the assumption and why.
    pub fn line(&self) -> String {
        match &self.assumed {
            None => format!("cutter radius {} mm (--cutter-radius)", self.radius),
            Some(why) => format!("cutter radius {} mm assumed: {why}", self.radius),
        }
    }
}

/// One line for each column where the table shows "-", saying why.
pub fn notes(found: &[Candidate], req: &Request) -> Vec<String> {
    let mut notes = Vec::new();
    if !found.is_empty() && req.rpm.is_none() {
        notes.push("\"-\" in cutter rpm and tip m/s: no --rpm (the lathe's speed) was given to work them out".into());
    }
    if found.iter().any(|c| c.min_cutter_radius.is_none()) {
        notes.push(match req.cutter_radius {
            Some(_) => "\"-\" in min R1 mm: the smallest cutter is worked out only when the cutter radius is assumed (no --cutter-radius)".into(),
            None => format!(
                "\"-\" in min R1 mm: no cutter radius up to {} mm keeps the flats within --tolerance {} mm in a section geometry takes",
                min_cutter_scan_top(req.stock_radius),
                req.tolerance
            ),
        });
    }
    notes
}
