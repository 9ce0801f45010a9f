//! The guided setup's arithmetic: the physical facts a
//! machinist knows (encoder lines, motor steps, microsteps, belt, top
//! speed), the settings they make and what those mean. No board here:
//! `polyturn device setup` asks and sends, and the web page's form sends
//! the same settings.

pub mod bldc;

use super::cutters::{refuse_others, For};
use super::errors::{CliError, CliResult};
use super::figures::{self, COMMON_RATIOS};
use super::values::{ratio, setting, setting_range, whole32, within};
use crate::geometry::Direction;
use polyturn_sync::config::table::{CPR, CUTTER_CPR, DIR_SETUP, MAX_RPM, PULSE, START_RATE};
use polyturn_sync::config::BldcOut;
use polyturn_sync::{DriveKind, Ratio, Sense};

#[derive(clap::Args, Debug, Clone)]
pub struct GuidedArgs {
    /// Ask nothing: every fact from the flags, no checks run (for scripts)
    #[arg(long)]
    pub non_interactive: bool,
    /// What turns the cutter: stepper (also a servo taking step/dir) or bldc (a BLDC with its own encoder, through a spindle driver or an RC ESC; the console's `drive`)
    #[arg(long, value_name = "stepper|bldc", default_value = "stepper", value_parser = crate::cli::values::drive)]
    pub drive: DriveKind,
    /// Encoder lines per turn, as on its label (counts = 4 x lines)
    #[arg(long, value_name = "N", value_parser = whole32(CPR.lo.div_ceil(4), CPR.hi / 4), conflicts_with = "encoder_cpr")]
    pub encoder_lines: Option<u32>,
    /// Measured encoder counts per lathe turn (from check-encoder)
    #[arg(long, value_name = "N", value_parser = setting(CPR))]
    pub encoder_cpr: Option<u32>,
    /// With --drive stepper: motor full steps per turn [default: 200]
    #[arg(long, value_name = "N", value_parser = whole32(1, 100_000))]
    pub motor_steps: Option<u32>,
    /// With --drive stepper: driver microsteps per full step [default: 16]
    #[arg(long, value_name = "N", value_parser = whole32(1, 512))]
    pub microsteps: Option<u32>,
    /// With --drive stepper: motor turns per cutter turn (belt or gears), greater than 0, e.g. 2, 40/20 or 40:20 (numerator and denominator 1..=1000, at most 6 decimal places) [default: 1]
    #[arg(long, value_name = "RATIO", value_parser = ratio)]
    pub reduction: Option<Ratio>,
    /// The lathe's fastest speed, rpm
    #[arg(long, value_name = "RPM", value_parser = setting(MAX_RPM))]
    pub max_lathe_rpm: Option<u32>,
    /// With --drive stepper: the driver's shortest STEP pulse, ns (its datasheet)
    #[arg(long, value_name = "NS", value_parser = setting(PULSE), conflicts_with = "pulse_us")]
    pub pulse_ns: Option<u32>,
    /// The same in microseconds: the old spelling, hidden, still taken
    #[arg(long, value_name = "US", value_parser = within(PULSE.lo as f64 / 1e3, PULSE.hi as f64 / 1e3, "us"), hide = true)]
    pub pulse_us: Option<f64>,
    /// With --drive stepper: the driver's DIR setup time before a STEP, ns
    #[arg(long, value_name = "NS", value_parser = setting(DIR_SETUP), conflicts_with = "dir_setup_us")]
    pub dir_setup_ns: Option<u32>,
    /// The same in microseconds: the old spelling, hidden, still taken
    #[arg(long, value_name = "US", value_parser = within(DIR_SETUP.lo as f64 / 1e3, DIR_SETUP.hi as f64 / 1e3, "us"), hide = true)]
    pub dir_setup_us: Option<f64>,
    /// The cutter's sense against the chuck's (seen from the same end): same or opposite (the console's `dir`)
    #[arg(long = "direction", alias = "sense", value_name = "same|opposite", default_value = "same", value_parser = crate::cli::values::direction)]
    pub sense: Direction,
    /// Counts fall when the lathe turns forward (check-encoder said so)
    #[arg(long)]
    pub encoder_reversed: bool,
    /// With dir=same, a jog turned the cutter against the chuck's forward turn
    #[arg(long)]
    pub motor_reversed: bool,
    /// Counts per cutter turn of an encoder on the motor's shaft or the cutter spindle (4 x lines x belt), on PB6/PB7: a stepper's lost-step alarm, or the BLDC's phase loop (the console's `steps`); 0 or off: none
    #[arg(long, value_name = "N", value_parser = cutter_cpr)]
    pub cutter_encoder_cpr: Option<u32>,
    /// With --drive stepper: the motor's start rate with the cutter fitted, steps/s: while following, a change of speed within it is made at once, so engaged at rest the cutter starts at the lathe's speed (at most the board's max-rate; 0: off, every change at max-accel; found on the bench)
    #[arg(long, value_name = "STEPS_PER_S", value_parser = setting(START_RATE))]
    pub start_rate: Option<u32>,
    #[command(flatten)]
    pub bldc: bldc::BldcArgs,
    /// Send the settings but do not save them
    #[arg(long)]
    pub no_save: bool,
}

/// The physical facts, however they were gathered.
#[derive(Clone, Debug)]
pub struct Facts {
    pub cpr: u32,
    pub steps: u32,
    pub max_rpm: u32,
    pub pulse_ns: Option<u32>,
    pub dir_setup_ns: Option<u32>,
    pub sense: Sense,
    pub encoder_reversed: bool,
    pub motor_reversed: bool,
    /// the shaft encoder's counts per cutter turn: Some(0) none, None not
    /// asked (the board's setting stays)
    pub cutter_cpr: Option<u32>,
    /// the motor's start rate, steps/s (0 off); None not asked (the
    /// board's setting stays)
    pub start_rate: Option<u32>,
    /// a BLDC cutter's drive (`steps` is then its encoder's counts); None:
    /// a stepper
    pub bldc: Option<bldc::BldcFacts>,
    /// a stepper set up on a board that holds a BLDC: the BLDC's
    /// `max-rate` and `ferror` go back to a stepper's (`stepper_rates`)
    pub after_bldc: bool,
}

/// A stepper's motor and driver unless told: 200 full steps, 16 microsteps.
pub const MOTOR_STEPS: u32 = 200;
pub const MICROSTEPS: u32 = 16;

/// `--cutter-encoder-cpr`: `off` or 0 (none), or the console's `cutter-cpr`.
fn cutter_cpr(v: &str) -> Result<u32, String> {
    match v.trim() {
        "off" => Ok(0),
        n => match n.parse::<u32>() {
            Ok(n) if n == 0 || CUTTER_CPR.contains(n) => Ok(n),
            _ => Err(format!("must be {} (0 is off too)", setting_range(CUTTER_CPR))),
        },
    }
}

/// Every flag that is one kind of cutter's, given or not.
fn cutters_flags(a: &GuidedArgs) -> [(&'static str, For, bool); 12] {
    let b = &a.bldc;
    [
        ("motor-steps", For::Stepper, a.motor_steps.is_some()),
        ("microsteps", For::Stepper, a.microsteps.is_some()),
        ("reduction", For::Stepper, a.reduction.is_some()),
        ("pulse-ns", For::Stepper, a.pulse_ns.is_some()),
        ("pulse-us", For::Stepper, a.pulse_us.is_some()),
        ("dir-setup-ns", For::Stepper, a.dir_setup_ns.is_some()),
        ("dir-setup-us", For::Stepper, a.dir_setup_us.is_some()),
        ("start-rate", For::Stepper, a.start_rate.is_some()),
        ("bldc-out", For::Bldc, b.bldc_out.is_some()),
        ("pwm-hz", For::Pwm, b.pwm_hz.is_some()),
        ("bldc-tau", For::Bldc, b.bldc_tau.is_some()),
        ("cutter-max-rpm", For::Bldc, b.cutter_max_rpm.is_some()),
    ]
}

pub fn from_flags(a: &GuidedArgs) -> CliResult<Facts> {
    refuse_others(a.drive, a.bldc.bldc_out == Some(BldcOut::Pwm), &cutters_flags(a))?;
    let need = |flag: &str| CliError::flag(flag, "is needed with --non-interactive");
    let cpr = match (a.encoder_cpr, a.encoder_lines) {
        (Some(c), _) => c,
        (None, Some(l)) => l * 4,
        (None, None) => return Err(need("encoder-lines (or --encoder-cpr)")),
    };
    let steps = match a.drive {
        DriveKind::Bldc => 0, // the BLDC's encoder's counts, below
        _ => motor_steps(a)?,
    };
    let stepper = Facts {
        cpr,
        steps,
        max_rpm: a.max_lathe_rpm.ok_or_else(|| need("max-lathe-rpm"))?,
        pulse_ns: a.pulse_ns.or(a.pulse_us.map(ns)),
        dir_setup_ns: a.dir_setup_ns.or(a.dir_setup_us.map(ns)),
        sense: sense_of(a.sense),
        encoder_reversed: a.encoder_reversed,
        motor_reversed: a.motor_reversed,
        cutter_cpr: a.cutter_encoder_cpr,
        start_rate: a.start_rate,
        bldc: None,
        after_bldc: false,
    };
    match a.drive {
        DriveKind::Bldc => bldc_facts(a, stepper),
        _ => Ok(stepper),
    }
}

/// A BLDC's facts in place of the stepper's (its flags refused above).
fn bldc_facts(a: &GuidedArgs, f: Facts) -> CliResult<Facts> {
    let b = bldc::from_flags(&a.bldc, a.cutter_encoder_cpr)?;
    Ok(Facts { steps: b.counts, cutter_cpr: None, bldc: Some(b), ..f })
}

/// Microseconds (the old `--pulse-us`, `--dir-setup-us`) as the
/// console's nanoseconds, rounded up: a driver's minimum is a minimum.
fn ns(us: f64) -> u32 {
    (us * 1000.0).ceil() as u32
}

pub fn sense_of(d: Direction) -> Sense {
    match d {
        Direction::Same => Sense::Same,
        Direction::Opposite => Sense::Opposite,
    }
}

/// A stepper's steps per cutter turn from its flags (or their defaults).
pub fn motor_steps(a: &GuidedArgs) -> CliResult<u32> {
    let r = a.reduction.map_or((1, 1), |r| (r.num() as u64, r.den() as u64));
    let (full, micro) = (a.motor_steps.unwrap_or(MOTOR_STEPS), a.microsteps.unwrap_or(MICROSTEPS));
    figures::steps_per_cutter_turn(full, micro, r)
        .map_err(|e| CliError(format!("--motor-steps x --microsteps x --reduction: {e}")))
}

/// The settings the facts make (the board checks each again).
pub fn changes(f: &Facts) -> Vec<(String, String)> {
    let dir = match figures::dir_setting(f.sense, f.encoder_reversed, f.motor_reversed) {
        Sense::Same => "same",
        Sense::Opposite => "opposite",
    };
    let mut c = vec![
        ("cpr".to_string(), f.cpr.to_string()),
        ("steps".to_string(), f.steps.to_string()),
        ("max-rpm".to_string(), f.max_rpm.to_string()),
        ("dir".to_string(), dir.to_string()),
    ];
    match &f.bldc {
        Some(b) => c.extend(bldc::changes(b)),
        None => c.push(("drive".into(), "stepper".into())),
    }
    if f.bldc.is_none() && f.after_bldc {
        c.extend(stepper_rates());
    }
    if let Some(p) = f.pulse_ns {
        c.push(("pulse".into(), p.to_string()));
    }
    if let Some(d) = f.dir_setup_ns {
        c.push(("dir-setup".into(), d.to_string()));
    }
    match f.cutter_cpr {
        Some(0) => c.push(("cutter-cpr".into(), "off".into())),
        Some(n) => c.push(("cutter-cpr".into(), n.to_string())),
        None => {}
    }
    if let Some(r) = f.start_rate {
        c.push(("start-rate".into(), r.to_string()));
    }
    c
}

/// What a BLDC's setup sets that binds a stepper, as a stepper's
/// defaults: `max-rate` (the BLDC's full speed in encoder counts/s, bounding
/// the stepper's steps and the lathe's speed) and `ferror` (twice the
/// BLDC's promise in counts, a few steps for a stepper).
pub fn stepper_rates() -> [(String, String); 2] {
    let d = polyturn_sync::Config::default();
    [
        ("max-rate".to_string(), d.max_step_rate_hz.to_string()),
        ("ferror".to_string(), d.following_error_limit_steps.to_string()),
    ]
}

/// The step rate a stepper's setup leaves on the board: a BLDC's
/// full speed is put back to a stepper's (`stepper_rates`).
pub fn stepper_max_rate(current: &polyturn_sync::Config) -> u32 {
    match current.drive {
        DriveKind::Bldc => polyturn_sync::Config::default().max_step_rate_hz,
        _ => current.max_step_rate_hz,
    }
}

/// Whether the lost-step alarm watches the cutter: a shaft encoder on a
/// stepper (or a step/dir servo).
fn lost_step_alarm(c: &polyturn_sync::Config) -> bool {
    c.cutter_encoder_cpr != 0 && c.drive == polyturn_sync::DriveKind::Stepper
}

/// What a start rate does, and what it risks (docs/src/bench.md,
/// "Finding the start rate").
fn start_rate_line(c: &polyturn_sync::Config) -> String {
    let caught = if lost_step_alarm(c) {
        "the lost-step alarm stops it"
    } else {
        "silently, with no shaft encoder: check it on the bench"
    };
    format!(
        "start-rate {} steps/s: engaged at rest, the cutter starts at the lathe's speed; a start faster than the motor pulls in with the cutter fitted loses steps ({caught})",
        c.start_rate_hz
    )
}

/// What the settings mean, for the machinist.
pub fn summary(c: &polyturn_sync::Config, sent: &[(String, String)]) -> String {
    let set: Vec<String> = sent.iter().map(|(n, v)| format!("{n}={v}")).collect();
    let (n, d) = figures::steps_per_count(c);
    // a BLDC's `steps` and `max-rate` are its encoder's counts
    let (per_count, rate) = match c.drive {
        polyturn_sync::DriveKind::Bldc => ("cutter encoder counts per lathe encoder count", "counts/s"),
        _ => ("motor steps per encoder count", "steps/s"),
    };
    let mut out = vec![
        format!("set: {}", set.join(" ")),
        format!("at ratio {}: {n}/{d} {per_count}", c.ratio),
        format!("fastest lathe speed (max-rate {} {rate}, max-rpm {}):", c.max_step_rate_hz, c.max_lathe_rpm),
    ];
    for &(num, den, what) in COMMON_RATIOS {
        let r = if den == 1 { format!("{num}") } else { format!("{num}/{den}") };
        out.push(format!("  ratio {r:>4}: {:>5} rpm  {what}", figures::fastest_lathe_rpm(c, num, den)));
    }
    if lost_step_alarm(c) {
        out.push(format!(
            "lost-step alarm: the shaft encoder's {} counts per cutter turn against the steps sent; it stops the cutter beyond {} steps (lost-steps)",
            c.cutter_encoder_cpr, c.lost_step_limit_steps
        ));
    }
    if c.start_rate_hz != 0 {
        out.push(start_rate_line(c));
    }
    if c.drive == polyturn_sync::DriveKind::Bldc {
        out.extend(bldc::lines(c, sent.iter().any(|(n, _)| n == "bldc-tau")));
    }
    out.join("\n")
}
