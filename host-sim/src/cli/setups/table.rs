//! `setups`' report: the table for a machinist, or JSON for programs (the
//! page's Plan view), both with what was assumed and what to beware of.

use super::advice::{self, Limits};
use super::assumed::Cutter;
use super::reproduce::Lines;
use crate::planner::{Candidate, Request};
use serde_json::{json, Value};

pub struct Report<'a> {
    pub req: &'a Request,
    pub found: &'a [Candidate],
    pub cutter: Cutter,
    pub lines: Option<Lines>,
    pub limits: Limits,
    /// what each "-" in the table means
    pub notes: Vec<String>,
    /// each shown as a `warning: ...` line
    pub warnings: Vec<String>,
}

impl Report<'_> {
    pub fn human(&self) -> String {
        let req = self.req;
        if self.found.is_empty() {
            // what was left out, and why, is said here too
            let none = format!(
                "no setup cuts {} sides within --max-edges {} and --max-ratio {}",
                req.sides, req.max_edges, req.max_ratio
            );
            return std::iter::once(&none).chain(&self.notes).cloned().collect::<Vec<_>>().join("\n");
        }
        let mut s = format!(
            "{} setups for {} sides from stock diameter {} mm, depth {:.3} mm (flattest first):\n{}\n",
            self.found.len(),
            req.sides,
            2.0 * req.stock_radius,
            req.depth,
            self.cutter.line()
        );
        s += "ratio  edges dir       turns  flat dev mm  corners  cutter rpm  tip m/s  min R1 mm\n";
        for c in self.found {
            s += &row(c);
        }
        for note in &self.notes {
            s += &format!("{note}\n");
        }
        if let Some(l) = &self.lines {
            s += &format!("the first row, to see and to prove it:\n  {}\n  {}\n", l.geometry, l.simulate);
        }
        for w in &self.warnings {
            s += &format!("warning: {w}\n");
        }
        s.trim_end().to_string()
    }

    /// The figures, what was assumed and the advice, for programs. Each
    /// row carries its own warnings, for the page to show beside it.
    pub fn json(&self) -> Value {
        let rows: Vec<Value> = self
            .found
            .iter()
            .map(|c| {
                let mut v = serde_json::to_value(c).unwrap_or(Value::Null);
                v["warnings"] = json!(advice::row(c, &self.limits));
                v
            })
            .collect();
        json!({
            "sides": self.req.sides,
            "depth": self.req.depth,
            "stock_diameter": 2.0 * self.req.stock_radius,
            "cutter_radius": self.cutter.radius,
            "cutter_radius_assumed": self.cutter.assumed,
            "geometry_command": self.lines.as_ref().map(|l| &l.geometry),
            "simulate_command": self.lines.as_ref().map(|l| &l.simulate),
            "notes": self.notes,
            "warnings": self.warnings,
            "setups": rows,
        })
    }
}

fn row(c: &Candidate) -> String {
    let opt = |v: Option<f64>, p: usize| v.map(|x| format!("{x:.p$}")).unwrap_or_else(|| "-".into());
    format!(
        "{:<6} {:<5} {:<9} {:<6} {:>+11.4}  {:<7}  {:>10}  {:>7}  {:>9}\n",
        c.ratio,
        c.edges,
        c.direction,
        c.revolutions,
        c.flat_deviation,
        if c.corners_sharp { "sharp" } else { "round" },
        opt(c.cutter_rpm, 0),
        opt(c.peak_tip_speed, 2),
        // as the planner rounded it: a figure `geometry` is checked with
        c.min_cutter_radius.map(|r| r.to_string()).unwrap_or_else(|| "-".into())
    )
}
