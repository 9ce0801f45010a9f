//! `polyturn simulate` and `polyturn demo`.

// the browser runs it in its own worker, with no terminal
#[cfg(not(target_family = "wasm"))]
mod alive;
mod refused;

use super::cutters::{refuse_others, For};
use super::errors::{CliError, CliResult, Failed};
use super::output::Outputs;
use super::setup_args::SetupArgs;
use super::values::{bldc_out, drive, out_file, pwm_hz, rpm, setting, whole, whole32, within};
use crate::geometry::{Direction, Setup};
use crate::sim::{report, run, Scenario, Start};
use polyturn_sync::config::table::{BLDC_TAU, CPR, START_RATE, STEPS};
use polyturn_sync::config::BldcOut;
use polyturn_sync::{DriveKind, Ratio};
use std::path::PathBuf;

/// The lathe time one run may simulate (bounds the work of any input).
const MAX_CUT_S: f64 = 600.0;

// Numbers take a leading '-' as a value (`--rpm -inf`), so that it is
// refused naming its flag rather than read as flags `-i -n -f`.
#[derive(clap::Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Lathe speed while cutting, rpm
    #[arg(long, value_name = "RPM", allow_hyphen_values = true, value_parser = rpm(6000.0))]
    pub rpm: f64,
    /// Lathe turns to cut; at most 600 s of cutting
    #[arg(long, value_name = "TURNS", allow_hyphen_values = true, value_parser = within(0.001, 10_000.0, "turns"))]
    pub revolutions: f64,
    /// Lathe speed ripple, a fraction of the speed
    #[arg(long, value_name = "FRACTION", default_value = "0", allow_hyphen_values = true, value_parser = within(0.0, 0.5, ""))]
    pub ripple: f64,
    /// Engage with the lathe at rest or already spinning: rest or spinning
    #[arg(long, value_name = "rest|spinning", default_value = "rest", value_parser = start)]
    pub start: Start,
    /// Lathe encoder counts per turn, after x4 quadrature
    #[arg(long, value_name = "COUNTS", default_value = "2400", allow_hyphen_values = true, value_parser = setting(CPR))]
    pub encoder_cpr: u32,
    /// Cutter motor steps per cutter turn, microsteps included (a BLDC: its encoder's counts)
    #[arg(long, value_name = "STEPS", default_value = "3200", allow_hyphen_values = true, value_parser = setting(STEPS))]
    pub motor_steps: u32,
    /// The cutter's drive: stepper or bldc
    #[arg(long, value_name = "stepper|bldc", default_value = "stepper", value_parser = drive)]
    pub drive: DriveKind,
    /// With --drive bldc: what the BLDC drive is fed: esc50, esc400, oneshot125 (an RC ESC) or pwm (a spindle driver's speed input) [default: esc50]
    #[arg(long, value_name = "esc50|esc400|oneshot125|pwm", value_parser = bldc_out)]
    pub bldc_out: Option<BldcOut>,
    /// With --bldc-out pwm: the PWM's frequency, Hz [default: 1000]
    #[arg(long, value_name = "HZ", allow_hyphen_values = true, value_parser = pwm_hz)]
    pub pwm_hz: Option<u32>,
    /// With --drive bldc: the drive's time constant as set (`bldc-tau`), ms [default: the simulated drive's own]
    #[arg(long, value_name = "MS", allow_hyphen_values = true, value_parser = setting(BLDC_TAU))]
    pub bldc_tau: Option<u32>,
    /// Seed of the simulated encoder noise and speed ripple
    #[arg(long, value_name = "S", default_value = "1", allow_hyphen_values = true, value_parser = whole(0, u64::MAX))]
    pub seed: u64,
    /// The cutter's `max-accel`, steps/s²; the simulated motor stalls past 5000000
    #[arg(long, value_name = "STEPS/S2", default_value = "400000", allow_hyphen_values = true, value_parser = whole32(10, 2_000_000))]
    pub max_accel: u32,
    /// With --drive stepper: the cutter's `start-rate`, speeds it takes and leaves at once, steps/s; 0: off [default: 0]
    #[arg(long, value_name = "STEPS/S", allow_hyphen_values = true, value_parser = setting(START_RATE))]
    pub start_rate: Option<u32>,
    /// Time the encoder's edges as the board does: on, or off (the count alone)
    #[arg(long, value_name = "on|off", default_value = "on", action = clap::ArgAction::Set, value_parser = on_off)]
    pub edge_timing: bool,
    /// Encoder disc eccentricity: edge error once a turn, counts
    #[arg(long, value_name = "COUNTS", default_value = "0", allow_hyphen_values = true, value_parser = within(0.0, 2.0, "counts"))]
    pub encoder_eccentricity: f64,
    /// Encoder B edges off their 90°, counts
    #[arg(long, value_name = "COUNTS", default_value = "0", allow_hyphen_values = true, value_parser = within(-0.45, 0.45, "counts"))]
    pub encoder_quadrature_error: f64,
    /// Encoder A's duty-cycle error, counts
    #[arg(long, value_name = "COUNTS", default_value = "0", allow_hyphen_values = true, value_parser = within(-0.45, 0.45, "counts"))]
    pub encoder_duty_error: f64,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
    /// Also draw the simulated section against the ideal to this SVG file (- for stdout)
    #[arg(long, value_name = "FILE", value_parser = out_file)]
    pub svg: Option<PathBuf>,
}

fn on_off(s: &str) -> Result<bool, String> {
    match s.trim() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err("must be 'on' or 'off'".into()),
    }
}

fn start(s: &str) -> Result<Start, String> {
    match s.trim() {
        "rest" => Ok(Start::Rest),
        "spinning" => Ok(Start::Spinning),
        _ => Err("must be 'rest' or 'spinning'".into()),
    }
}

pub fn scenario_from(a: &SimulateArgs) -> CliResult<Scenario> {
    let pwm = a.bldc_out == Some(BldcOut::Pwm);
    let flags = [
        ("bldc-out", For::Bldc, a.bldc_out.is_some()),
        ("pwm-hz", For::Pwm, a.pwm_hz.is_some()),
        ("bldc-tau", For::Bldc, a.bldc_tau.is_some()),
        ("start-rate", For::Stepper, a.start_rate.is_some()),
    ];
    refuse_others(a.drive, pwm, &flags)?;
    let setup = a.setup.setup()?;
    let (rpm, revs) = (a.rpm, a.revolutions);
    let seconds = revs * 60.0 / rpm;
    if seconds > MAX_CUT_S {
        return Err(CliError::flag(
            "revolutions",
            format!("would simulate {seconds:.0} s of cutting at {rpm} rpm: at most {MAX_CUT_S} s (lower it, or raise --rpm)"),
        ));
    }
    let mut sc = Scenario::standard(setup, rpm, revs, a.ripple, a.start, a.encoder_cpr, a.motor_steps, a.drive, a.seed);
    sc.edge_timing = a.edge_timing;
    sc.core.max_accel_steps_per_s2 = a.max_accel;
    sc.core.start_rate_hz = a.start_rate.unwrap_or(0);
    if a.drive == DriveKind::Bldc {
        fit_bldc(&mut sc, a)?;
    }
    sc.disc = crate::sim::encoder::Disc {
        eccentricity_counts: a.encoder_eccentricity,
        quadrature_counts: a.encoder_quadrature_error,
        duty_counts: a.encoder_duty_error,
    };
    sc.core.validate().map_err(|e| refused::setting(e, &sc.core, a))?;
    Ok(sc)
}

/// The BLDC's drive fitted to the run; a time constant of its own out of
/// `bldc-tau`'s range is named with where it came from.
fn fit_bldc(sc: &mut Scenario, a: &SimulateArgs) -> CliResult<()> {
    let out = a.bldc_out.unwrap_or(BldcOut::Esc50);
    if a.bldc_tau.is_none() {
        refused::own_tau(sc, out, a.motor_steps)?;
    }
    let pwm_hz = a.pwm_hz.unwrap_or(1_000);
    // refused, it is named with the drive as fitted, not the board's default
    let tau = a.bldc_tau.unwrap_or(crate::sim::bldc_drive::own_tau_ms(sc, out));
    let fitted = polyturn_sync::Config { bldc_out: out, pwm_hz, bldc_tau_ms: tau, ..sc.core };
    crate::sim::bldc_drive::fit_drive(sc, out, pwm_hz, a.bldc_tau).map_err(|e| refused::setting(e, &fitted, a))
}

/// A run that cut nothing, too little or not the polygon fails with no
/// report; one whose controller latched a fault anyway fails with it.
pub fn run_cli(a: SimulateArgs) -> Result<String, Failed> {
    let sc = scenario_from(&a)?;
    #[cfg(not(target_family = "wasm"))]
    let r = alive::run_alive(&sc, a.revolutions, a.rpm);
    #[cfg(target_family = "wasm")]
    let r = run(&sc);
    let r = r.map_err(CliError)?;
    if r.cut_turns == 0.0 {
        return Err(refused::nothing_cut(&sc, &r, &a).into());
    }
    // a fault that stopped the cut is why it is short, not --revolutions
    let short = || refused::stopped_by_fault(&sc, &r, &a).or_else(|| refused::cut_short(&sc, &r, &a));
    if let Some(e) = short().or_else(|| refused::missed(&sc, &r, &a)) {
        return Err(e.into());
    }
    let report = if a.json { report::json(&sc, &r).to_string() } else { report::human(&sc, &r) };
    // a failed run writes no file (tools.md): the report alone says it
    if let Some(error) = refused::latched(&sc, &r, &a) {
        return Err(Failed { report: Some(report), error });
    }
    let mut files = Outputs::default();
    if let Some(path) = &a.svg {
        files.add("svg", path, report::svg(&sc, &r))?;
    }
    Ok(files.write()?.report(report))
}

#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Where to draw the hexagon (- for stdout)
    #[arg(long, value_name = "FILE", default_value = "hexagon.svg", value_parser = out_file)]
    pub svg: PathBuf,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
}

/// The README's first command: the hexagon, end to end, writes hexagon.svg.
pub fn demo(a: DemoArgs) -> CliResult<String> {
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
    let mut files = Outputs::default();
    files.add("svg", &a.svg, report::svg(&sc, &r))?;
    let written = files.write()?;
    if a.json {
        return Ok(written.report(report::json(&sc, &r).to_string()));
    }
    let path = super::output::named(&a.svg);
    Ok(written.report(format!(
        "polyturn demo: a hexagon from 2:1 x 3 edges at 600 rpm (2 % speed ripple), simulated end to end\n{}\nwrote {path}",
        report::human(&sc, &r)
    )))
}
