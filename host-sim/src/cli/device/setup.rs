//! `polyturn device setup`: the guided setup (issue 14). It asks only
//! physical facts (the encoder, the motor and its driver, the belt, the
//! lathe's top speed), runs the encoder check and a jog on the board,
//! derives the settings, sends them in an order the board accepts, shows
//! what they mean (steps per count, the fastest lathe speed per ratio) and
//! saves. `--non-interactive` takes every fact from flags, for scripts.

use super::checks::{self, Turning};
use super::figures::{self, COMMON_RATIOS};
use super::prompt::Ask;
use super::session::{ok_or_device_error, Session};
use crate::cli::errors::{CliError, CliResult};
use crate::cli::values::{ratio, whole32, within};
use crate::geometry::Direction;
use polyturn_sync::{Ratio, Sense};
use std::io::{Read, Write};

#[derive(clap::Args, Debug, Clone)]
pub struct SetupArgs {
    /// Ask nothing: every fact from the flags, no checks run (for scripts)
    #[arg(long)]
    pub non_interactive: bool,
    /// Encoder lines per turn, as on its label (counts = 4 x lines)
    #[arg(long, value_name = "N", value_parser = whole32(1, 250_000), conflicts_with = "encoder_cpr")]
    pub encoder_lines: Option<u32>,
    /// Measured encoder counts per lathe turn (from check-encoder)
    #[arg(long, value_name = "N", value_parser = whole32(4, 1_000_000))]
    pub encoder_cpr: Option<u32>,
    /// Motor full steps per turn
    #[arg(long, value_name = "N", default_value = "200", value_parser = whole32(1, 100_000))]
    pub motor_steps: u32,
    /// Driver microsteps per full step
    #[arg(long, value_name = "N", default_value = "16", value_parser = whole32(1, 512))]
    pub microsteps: u32,
    /// Motor turns per cutter turn (belt or gears), e.g. 2 or 40/20
    #[arg(long, value_name = "RATIO", default_value = "1", value_parser = ratio)]
    pub reduction: Ratio,
    /// The lathe's fastest speed, rpm
    #[arg(long, value_name = "RPM", value_parser = whole32(1, 10_000))]
    pub max_lathe_rpm: Option<u32>,
    /// The driver's shortest STEP pulse, microseconds (its datasheet)
    #[arg(long, value_name = "US", value_parser = within(1.0, 1000.0, "us"))]
    pub pulse_us: Option<f64>,
    /// The driver's DIR setup time before a STEP, microseconds
    #[arg(long, value_name = "US", value_parser = within(0.0, 1000.0, "us"))]
    pub dir_setup_us: Option<f64>,
    /// The cutter's sense against the chuck's (seen from the same end)
    #[arg(long, value_name = "SENSE", default_value = "same", value_parser = crate::cli::values::direction)]
    pub sense: Direction,
    /// Counts fall when the lathe turns forward (check-encoder said so)
    #[arg(long)]
    pub encoder_reversed: bool,
    /// With dir=same, a jog turned the cutter against the chuck's forward turn
    #[arg(long)]
    pub motor_reversed: bool,
    /// Send the settings but do not save them
    #[arg(long)]
    pub no_save: bool,
}

/// The physical facts, however they were gathered.
#[derive(Clone, Debug)]
struct Facts {
    cpr: u32,
    steps: u32,
    max_rpm: u32,
    pulse_ns: Option<u32>,
    dir_setup_ns: Option<u32>,
    sense: Sense,
    encoder_reversed: bool,
    motor_reversed: bool,
}

pub fn run<P: Read + Write>(s: &mut Session<P>, a: &SetupArgs, ask: &mut dyn Ask) -> CliResult<String> {
    let facts = if a.non_interactive { from_flags(a)? } else { interview(s, a, ask)? };
    let current = figures::parse_settings(&s.ask("get")?)
        .ok_or_else(|| s.port_error("its settings could not be read (get): flash this version"))?;
    let (order, now) = figures::send_order(&current, &changes(&facts)).map_err(CliError)?;
    for (name, value) in &order {
        s.ask(&format!("set {name} {value}"))?;
    }
    if !a.non_interactive {
        clear_check_fault(s, ask)?;
        jog_check(s, ask)?;
    }
    let saved = if a.no_save {
        "not saved (--no-save): the settings last until the board restarts".to_string()
    } else {
        ok_or_device_error(s.ask_within("save", super::FLASH_WAIT.max(s.timeout))?)?
    };
    Ok(format!("{}\n{saved}", summary(&now, &order)))
}

fn from_flags(a: &SetupArgs) -> CliResult<Facts> {
    let need = |flag: &str| CliError::flag(flag, "is needed with --non-interactive");
    let cpr = match (a.encoder_cpr, a.encoder_lines) {
        (Some(c), _) => c,
        (None, Some(l)) => l * 4,
        (None, None) => return Err(need("encoder-lines (or --encoder-cpr)")),
    };
    Ok(Facts {
        cpr,
        steps: motor_steps(a)?,
        max_rpm: a.max_lathe_rpm.ok_or_else(|| need("max-lathe-rpm"))?,
        pulse_ns: a.pulse_us.map(|us| (us * 1000.0).ceil() as u32),
        dir_setup_ns: a.dir_setup_us.map(|us| (us * 1000.0).ceil() as u32),
        sense: sense_of(a.sense),
        encoder_reversed: a.encoder_reversed,
        motor_reversed: a.motor_reversed,
    })
}

fn sense_of(d: Direction) -> Sense {
    match d {
        Direction::Same => Sense::Same,
        Direction::Opposite => Sense::Opposite,
    }
}

fn motor_steps(a: &SetupArgs) -> CliResult<u32> {
    let r = (a.reduction.num() as u64, a.reduction.den() as u64);
    figures::steps_per_cutter_turn(a.motor_steps, a.microsteps, r).map_err(|e| CliError::flag("reduction", e))
}

/// The settings the facts make (the board checks each again).
fn changes(f: &Facts) -> Vec<(String, String)> {
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
    if let Some(p) = f.pulse_ns {
        c.push(("pulse".into(), p.to_string()));
    }
    if let Some(d) = f.dir_setup_ns {
        c.push(("dir-setup".into(), d.to_string()));
    }
    c
}

/// What the settings mean, for the machinist.
fn summary(c: &polyturn_sync::Config, sent: &[(String, String)]) -> String {
    let set: Vec<String> = sent.iter().map(|(n, v)| format!("{n}={v}")).collect();
    let (n, d) = figures::steps_per_count(c);
    let mut out = vec![
        format!("set: {}", set.join(" ")),
        format!("at ratio {}: {n}/{d} motor steps per encoder count", c.ratio),
        format!("fastest lathe speed (max-rate {} steps/s, max-rpm {}):", c.max_step_rate_hz, c.max_lathe_rpm),
    ];
    for &(num, den, what) in COMMON_RATIOS {
        let r = if den == 1 { format!("{num}") } else { format!("{num}/{den}") };
        out.push(format!("  ratio {r:>4}: {:>5} rpm  {what}", figures::fastest_lathe_rpm(c, num, den)));
    }
    out.join("\n")
}

/// The questions, with the encoder check on the board.
fn interview<P: Read + Write>(s: &mut Session<P>, a: &SetupArgs, ask: &mut dyn Ask) -> CliResult<Facts> {
    ask.say("polyturn setup: physical facts only; the board measures what it can.");
    let index = ask.yes("Does the lathe encoder have an index (Z) pulse wired to PB0?", true)?;
    let turns = if index { None } else { Some(ask.number("How many chuck turns will you make?", Some(3), 1, 20)?) };
    let (f, proposal) = checks::check_encoder(s, ask, Turning::UntilEnter, turns)?;
    ask.say(&checks::explain(&f, &proposal));
    let cpr = match proposal {
        Ok(c) if ask.yes(&format!("Use cpr {c}?"), true)? => c,
        _ => 4 * ask.number("Encoder lines per turn, from its label", a.encoder_lines, 1, 250_000)?,
    };
    let full = ask.number("Motor full steps per turn", Some(a.motor_steps), 1, 100_000)?;
    let micro = ask.number("Driver microsteps", Some(a.microsteps), 1, 512)?;
    let belt = ask.choose("Between motor and cutter", &["direct", "belt or gears"])?;
    let reduction = if belt == 0 {
        (1, 1)
    } else {
        (
            ask.number("Cutter pulley teeth", None, 1, 1000)? as u64,
            ask.number("Motor pulley teeth", None, 1, 1000)? as u64,
        )
    };
    let steps = figures::steps_per_cutter_turn(full, micro, reduction).map_err(CliError)?;
    let sense = match ask.choose("The cutter turns, against the chuck", &["same", "opposite"])? {
        0 => Sense::Same,
        _ => Sense::Opposite,
    };
    Ok(Facts {
        cpr,
        steps,
        max_rpm: ask.number("The lathe's fastest speed, rpm", a.max_lathe_rpm.or(Some(1500)), 1, 10_000)?,
        pulse_ns: Some(ask.number(
            "The driver's shortest STEP pulse, ns (its datasheet; 2500 if unsure)",
            Some(2500),
            1000,
            1_000_000,
        )?),
        dir_setup_ns: Some(ask.number("The driver's DIR setup time, ns (5000 if unsure)", Some(5000), 0, 1_000_000)?),
        sense,
        encoder_reversed: f.moved < 0,
        motor_reversed: false,
    })
}

/// The encoder check turns the lathe under the old cpr, whose index
/// check then trips `encoder-implausible`: cleared now that cpr is right.
/// Any other fault stops the setup (an open E-stop, say).
fn clear_check_fault<P: Read + Write>(s: &mut Session<P>, ask: &mut dyn Ask) -> CliResult<()> {
    let status = s.ask("status")?;
    if status.contains("fault=encoder-implausible") {
        s.ask("clear")?;
        ask.say("cleared encoder-implausible: the check's index pulses did not match the old cpr");
    } else if !status.contains("fault=none") {
        return Err(CliError(format!(
            "device: {}: clear it before the cutter check (settings sent, not saved)",
            status.trim_start_matches("ok ")
        )));
    }
    Ok(())
}

/// One cutter turn on the board, and the machinist's eyes: the steps and
/// the direction are corrected if it was not one turn the right way.
fn jog_check<P: Read + Write>(s: &mut Session<P>, ask: &mut dyn Ask) -> CliResult<()> {
    ask.wait("Cutter check: the cutter will turn once, slowly. Keep clear, then press Enter")?;
    ask.say(&checks::jog(s, "360")?);
    let turned = ask.choose("How far did it turn?", &["one turn", "half a turn", "two turns", "other"])?;
    if turned != 0 {
        ask.say("Set the driver's microsteps to match, or `polyturn device set steps N` with N = steps x (commanded turns / real turns), then run setup again.");
        return Err(CliError("setup: the cutter did not make one turn: nothing saved".into()));
    }
    if !ask.yes("Did it turn the way you chose (same or opposite to the chuck turning forward)?", true)? {
        let dir = s.ask("get dir")?;
        let flipped = if dir.contains("dir=same") { "opposite" } else { "same" };
        s.ask(&format!("set dir {flipped}"))?;
        ask.say(&format!("dir set to {flipped}"));
    }
    Ok(())
}

#[cfg(test)]
#[path = "setup_tests.rs"]
mod tests;
