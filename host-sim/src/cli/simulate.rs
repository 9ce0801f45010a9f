//! `polyturn simulate` and `polyturn demo`.

use super::args::{Args, CliError, CliResult};
use super::geometry::setup_from;
use crate::geometry::{Direction, Setup};
use crate::sim::{report, run, Scenario, Start};
use polyturn_sync::{DriveKind, Ratio};

pub const USAGE: &str = "polyturn simulate --ratio GR --edges Z --direction same|opposite --cutter-radius R1 --stock-radius R2 --depth DOC --rpm RPM --revolutions N [--ripple F] [--start rest|spinning] [--encoder-cpr E] [--motor-steps M] [--drive stepper|bldc] [--seed S] [--json] [--svg FILE]";
const VALUED: &[&str] = &[
    "cutter-radius",
    "stock-radius",
    "depth",
    "ratio",
    "edges",
    "direction",
    "svg",
    "rpm",
    "revolutions",
    "ripple",
    "start",
    "encoder-cpr",
    "motor-steps",
    "drive",
    "seed",
];

pub fn scenario_from(args: &Args) -> CliResult<Scenario> {
    let setup = setup_from(args)?;
    let rpm = args.number("rpm", 0.0, 6000.0, true, "rpm")?.ok_or_else(|| CliError::flag("rpm", "is required"))?;
    let revs = args
        .number("revolutions", 0.0, 10_000.0, true, "revolutions")?
        .ok_or_else(|| CliError::flag("revolutions", "is required"))?;
    // Bound the work: at most 10 minutes of lathe time at the set speed.
    if revs * 60.0 / rpm > 600.0 {
        return Err(CliError::flag(
            "revolutions",
            format!(
                "would simulate {:.0} s of cutting at {rpm} rpm: at most 600 s (lower it, or raise --rpm)",
                revs * 60.0 / rpm
            ),
        ));
    }
    let ripple = args.number("ripple", 0.0, 0.5, false, "(fraction of speed)")?.unwrap_or(0.0);
    let start = match args.choice("start", &["rest", "spinning"], "rest")? {
        "spinning" => Start::Spinning,
        _ => Start::Rest,
    };
    let cpr = args.whole("encoder-cpr", 4, 1_000_000)?.unwrap_or(2400) as u32;
    let steps = args.whole("motor-steps", 1, 1_000_000)?.unwrap_or(3200) as u32;
    let drive = match args.choice("drive", &["stepper", "bldc"], "stepper")? {
        "bldc" => DriveKind::Bldc,
        _ => DriveKind::Stepper,
    };
    let seed = args.whole("seed", 0, u64::MAX)?.unwrap_or(1);
    let sc = Scenario::standard(setup, rpm, revs, ripple, start, cpr, steps, drive, seed);
    // Refuse, with the reason, a run whose motor would overspeed.
    sc.core.validate().map_err(|e| match e.field {
        "ratio" => CliError::flag("rpm", format!("too fast for this ratio and motor: needs {:.0} steps/s, the motor's limit is {} (lower --rpm or --motor-steps)", sc.core.motor_rate_at(rpm), sc.core.max_step_rate_hz)),
        f => CliError::flag(f, e.allowed),
    })?;
    Ok(sc)
}

pub fn run_cli(argv: &[String]) -> CliResult<String> {
    let args = Args::parse(argv, VALUED, &["json"])?;
    let sc = scenario_from(&args)?;
    let r = run(&sc).map_err(CliError)?;
    if let Some(path) = args.raw("svg") {
        std::fs::write(path, report::svg(&sc, &r))
            .map_err(|e| CliError::flag("svg", format!("could not write '{path}': {e}")))?;
    }
    Ok(if args.has("json") { report::json(&sc, &r).to_string() } else { report::human(&sc, &r) })
}

/// The README's first command: the hexagon, end to end, writes hexagon.svg.
pub fn demo(argv: &[String]) -> CliResult<String> {
    let args = Args::parse(argv, &["svg"], &["json"])?;
    let setup = Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 1.5,
        ratio: Ratio::new(2, 1).map_err(|e| CliError(e.describe().into()))?,
        edges: 3,
        direction: Direction::Same,
    };
    let sc = Scenario::standard(setup, 600.0, 20.0, 0.02, Start::Rest, 2400, 3200, DriveKind::Stepper, 1);
    let r = run(&sc).map_err(CliError)?;
    let path = args.raw("svg").unwrap_or("hexagon.svg");
    std::fs::write(path, report::svg(&sc, &r))
        .map_err(|e| CliError::flag("svg", format!("could not write '{path}': {e}")))?;
    if args.has("json") {
        return Ok(report::json(&sc, &r).to_string());
    }
    Ok(format!(
        "polyturn demo: a hexagon from 2:1 x 3 edges at 600 rpm (2 % speed ripple), simulated end to end\n{}\nwrote {path}",
        report::human(&sc, &r)
    ))
}
