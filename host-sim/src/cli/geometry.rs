//! `polyturn geometry`: what polygon a setup cuts.

use super::errors::CliResult;
use super::measure::{across_corners, calipers};
use super::output::Outputs;
use super::setup_args::SetupArgs;
use crate::geometry::{svg, Section, SectionSummary, Setup};
use serde_json::json;
use std::path::PathBuf;

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
        "across_corners": across_corners(&s),
        "flat_deviation": s.flat_deviation,
        "corners_sharp": s.corners_sharp,
        "ratio": setup.ratio.to_string(),
        "edges": setup.edges,
        "direction": setup.direction.name(),
        "cutter_radius": setup.cutter_radius_mm,
        "stock_radius": setup.stock_radius_mm,
        "stock_diameter": 2.0 * setup.stock_radius_mm,
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
    let text = if a.json { report(&setup, &section).to_string() } else { human(&setup, &section.summary()) };
    Ok(written.report(text))
}

/// The report for a machinist: the stock as calipers read it (its
/// diameter), and the section as they will read it (across flats and
/// across corners).
fn human(setup: &Setup, s: &SectionSummary) -> String {
    format!(
        "{} over {} lathe turn(s): ratio {} x {} edges, {} sense\n\
         stock diameter {:.4} mm, depth {:.4} mm, cutter radius {:.4} mm\n\
         inscribed radius {:.4} mm, circumscribed {:.4} mm, {}\n\
         flat deviation {:+.4} mm ({}), corners {}",
        if s.sides == 1 { "1 side".to_string() } else { format!("{} sides", s.sides) },
        setup.pattern().1,
        setup.ratio,
        setup.edges,
        setup.direction.name(),
        2.0 * setup.stock_radius_mm,
        setup.depth_mm,
        setup.cutter_radius_mm,
        s.inscribed_radius,
        s.circumscribed_radius,
        calipers(s),
        s.flat_deviation,
        if s.flat_deviation >= 0.0 { "convex" } else { "concave" },
        if s.corners_sharp { "sharp" } else { "left round (stock at the corners)" },
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
