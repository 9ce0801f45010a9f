//! `polyturn geometry`: what polygon a setup cuts.

use super::errors::{CliError, CliResult};
use super::output::Outputs;
use super::values::{direction, length_mm, ratio, whole32};
use crate::geometry::{svg, Direction, Section, Setup};
use polyturn_sync::Ratio;
use serde_json::json;
use std::path::PathBuf;

/// The six variables of a setup (Foale's R1, R2, DOC, GR, Z and sense),
/// shared by geometry, simulate and compensate.
#[derive(clap::Args, Debug)]
pub struct SetupArgs {
    /// Cutter radius R1: the cutting edge's distance from the cutter's axis, mm (> --depth)
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub cutter_radius: f64,
    /// Stock radius R2 before the cut, mm (<= 10000)
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub stock_radius: f64,
    /// Depth of cut DOC at the flats' middle, mm (> 0, < --stock-radius)
    #[arg(long, value_name = "MM", value_parser = length_mm())]
    pub depth: f64,
    /// Gear ratio GR, cutter turns per lathe turn: 2, 5/2 or 2.5 (numerator and denominator 1..=1000)
    #[arg(long, value_name = "GR", value_parser = ratio)]
    pub ratio: Ratio,
    /// Cutting edges Z on the cutter (1..=12)
    #[arg(long, value_name = "Z", value_parser = whole32(1, 12))]
    pub edges: u32,
    /// The cutter's sense against the lathe's: same or opposite
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
        let setup = Setup {
            cutter_radius_mm: self.cutter_radius,
            stock_radius_mm: self.stock_radius,
            depth_mm: self.depth,
            ratio: self.ratio,
            edges: self.edges,
            direction: self.direction,
        };
        setup.validate().map_err(|e| CliError::flag(e.field, e.allowed))?;
        let section = Section::ideal(&setup, Section::default_bins(setup.sides()));
        not_round(&section.summary())?;
        Ok((setup, section))
    }
}

#[derive(clap::Args, Debug)]
pub struct GeometryArgs {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
    /// Also draw the section and the cutter's tip traces to this SVG file
    #[arg(long, value_name = "FILE", value_parser = super::values::out_file)]
    pub svg: Option<PathBuf>,
}

/// The contract's JSON object for a setup and its section.
pub fn report(setup: &Setup, section: &Section) -> serde_json::Value {
    let s = section.summary();
    let (_, revolutions) = setup.pattern();
    json!({
        "sides": s.sides,
        "revolutions": revolutions,
        "inscribed_radius": s.inscribed_radius,
        "circumscribed_radius": s.circumscribed_radius,
        "across_flats": s.across_flats,
        "flat_deviation": s.flat_deviation,
        "corners_sharp": s.corners_sharp,
        "ratio": setup.ratio.to_string(),
        "edges": setup.edges,
        "direction": setup.direction.name(),
        "cutter_radius": setup.cutter_radius_mm,
        "stock_radius": setup.stock_radius_mm,
        "depth": setup.depth_mm,
        "centre_distance": setup.centre_distance(),
    })
}

pub fn run(a: GeometryArgs) -> CliResult<String> {
    let (setup, section) = a.setup.setup_and_section()?;
    let mut files = Outputs::default();
    if let Some(path) = &a.svg {
        files.add("svg", path, draw(&setup, &section))?;
    }
    let written = files.write()?;
    let r = report(&setup, &section);
    Ok(written.report(if a.json { r.to_string() } else { human(&r) }))
}

/// A circle has N "flats" too, each bulging R(1 - cos(pi/N)) from its
/// chord. A section whose flats bulge more than half that is round to the
/// eye and the finger: not reported as a polygon (issue 13: a 0.002 mm
/// cutter's shaved circle came out as 6 sharp sides).
pub const ROUND_FRACTION: f64 = 0.5;

fn not_round(s: &crate::geometry::SectionSummary) -> CliResult<()> {
    let circle = s.circumscribed_radius * (1.0 - (std::f64::consts::PI / s.sides as f64).cos());
    let fraction = s.flat_deviation.abs() / circle;
    if fraction > ROUND_FRACTION {
        return Err(CliError::flag(
            "cutter-radius",
            format!("is too small for this depth: the section is nearly round (its flats bulge {:.0} % as much as a circle's); a larger cutter gives flatter sides", fraction * 100.0),
        ));
    }
    Ok(())
}

fn human(r: &serde_json::Value) -> String {
    let af = match r["across_flats"].as_f64() {
        Some(v) => format!("{v:.4} mm"),
        None => "n/a (odd sides)".into(),
    };
    format!(
        "{} sides over {} lathe turn(s): ratio {} x {} edges, {} sense\n\
         inscribed radius {:.4} mm, circumscribed {:.4} mm, across flats {af}\n\
         flat deviation {:+.4} mm ({}), corners {}",
        r["sides"],
        r["revolutions"],
        r["ratio"].as_str().unwrap_or(""),
        r["edges"],
        r["direction"].as_str().unwrap_or(""),
        r["inscribed_radius"].as_f64().unwrap_or(0.0),
        r["circumscribed_radius"].as_f64().unwrap_or(0.0),
        r["flat_deviation"].as_f64().unwrap_or(0.0),
        if r["flat_deviation"].as_f64().unwrap_or(0.0) >= 0.0 { "convex" } else { "concave" },
        if r["corners_sharp"].as_bool() == Some(true) { "sharp" } else { "left round (stock at the corners)" },
    )
}

/// Stock circle, section, and (thin) every pass's tip trace.
pub fn draw(setup: &Setup, section: &Section) -> String {
    let r2 = setup.stock_radius_mm;
    let mut d = svg::Drawing::new(r2 * 1.4, 560.0);
    d.circle(r2, r##"fill="none" stroke="#c33" stroke-width="1.5""##);
    d.path(&svg::outline(&section.envelope), true, r##"fill="#3569" stroke="#124" stroke-width="1.5""##);
    let pass = crate::geometry::section::pass_points(setup, 600);
    let n = setup.sides();
    for j in 0..n.min(64) {
        let t = std::f64::consts::TAU * j as f64 / n as f64;
        let (s, c) = t.sin_cos();
        let rotated: Vec<_> = pass.iter().map(|&(x, y)| (x * c - y * s, x * s + y * c)).collect();
        d.path(&rotated, false, r##"fill="none" stroke="#79a" stroke-width="0.5""##);
    }
    let s = section.summary();
    d.text(
        0,
        &format!("{} sides: ratio {} x {} edges, {} sense", s.sides, setup.ratio, setup.edges, setup.direction.name()),
    );
    d.text(1, &format!("R1 {} R2 {} DOC {} mm", setup.cutter_radius_mm, r2, setup.depth_mm));
    let af = s.across_flats.map(|v| format!(", across flats {v:.3}")).unwrap_or_default();
    d.text(2, &format!("inscribed {:.3} mm{af}", s.inscribed_radius));
    d.text(
        3,
        &format!(
            "flat deviation {:+.4} mm, corners {}",
            s.flat_deviation,
            if s.corners_sharp { "sharp" } else { "round" }
        ),
    );
    d.finish(560.0)
}
