//! `polyturn geometry`: what polygon a setup cuts.

use super::args::{Args, CliError, CliResult};
use crate::geometry::{svg, Section, Setup};
use serde_json::json;

pub const USAGE: &str = "polyturn geometry --cutter-radius R1 --stock-radius R2 --depth DOC --ratio GR --edges Z --direction same|opposite [--json] [--svg FILE]";
const VALUED: &[&str] = &["cutter-radius", "stock-radius", "depth", "ratio", "edges", "direction", "svg"];

/// Reads and validates the five variables shared by geometry and simulate.
pub fn setup_from(args: &Args) -> CliResult<Setup> {
    let setup = Setup {
        cutter_radius_mm: args.required_length_mm("cutter-radius")?,
        stock_radius_mm: args.required_length_mm("stock-radius")?,
        depth_mm: {
            args.required("depth")?;
            args.number("depth", 0.0, 10_000.0, true, "mm")?.unwrap_or_default()
        },
        ratio: args.ratio("ratio")?,
        edges: {
            args.required("edges")?;
            args.whole("edges", 1, 12)?.unwrap_or_default() as u32
        },
        direction: args.direction("direction")?,
    };
    setup.validate().map_err(|e| CliError::flag(e.field, e.allowed))?;
    Ok(setup)
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

pub fn run(argv: &[String]) -> CliResult<String> {
    let args = Args::parse(argv, VALUED, &["json"])?;
    let setup = setup_from(&args)?;
    let section = Section::ideal(&setup, Section::default_bins(setup.sides()));
    if let Some(path) = args.raw("svg") {
        std::fs::write(path, draw(&setup, &section))
            .map_err(|e| CliError::flag("svg", format!("could not write '{path}': {e}")))?;
    }
    let r = report(&setup, &section);
    Ok(if args.has("json") { r.to_string() } else { human(&r) })
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
