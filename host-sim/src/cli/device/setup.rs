//! `polyturn device setup`: the guided setup. It asks only
//! physical facts (the encoder, the motor and its driver, the belt, the
//! lathe's top speed), runs the encoder check and a jog on the board,
//! derives the settings, sends them in an order the board accepts, saves,
//! and shows what the board then holds, read back (steps per count, the
//! fastest lathe speed per ratio). Every question takes the console's own
//! range for the setting it makes (`polyturn_sync::config::table`).
//! `--non-interactive` takes every fact from flags, for scripts.

use super::checks::{self, Turning};
use super::figures;
use super::prompt::{retry, Ask};
use super::session::{ok_or_device_error, Session};
use crate::cli::errors::{CliError, CliResult};
pub use crate::cli::guided::GuidedArgs;
use crate::cli::guided::{changes, from_flags, stepper_max_rate, summary, Facts, MICROSTEPS, MOTOR_STEPS};
use polyturn_sync::config::table::{CPR, CUTTER_CPR, DIR_SETUP, MAX_RPM, PULSE, START_RATE};
use polyturn_sync::{Config, DriveKind, Sense};
use std::io::{Read, Write};

mod drive;

pub fn run<P: Read + Write>(s: &mut Session<P>, a: &GuidedArgs, ask: &mut dyn Ask) -> CliResult<String> {
    let facts = if a.non_interactive { from_flags(a)? } else { interview(s, a, ask)? };
    let (_, current) = read_back(s)?;
    let facts = Facts { after_bldc: facts.bldc.is_none() && current.drive == DriveKind::Bldc, ..facts };
    if a.non_interactive {
        within_the_step_rate(&facts, &current, a)?;
    }
    let facts = top_speed_that_fits(facts, &current, a, ask)?;
    let (order, next) = figures::send_order(&current, &changes(&facts)).map_err(CliError)?;
    cam_keeps_its_cutter(s, &current, &next)?;
    for (name, value) in &order {
        s.ask(&format!("set {name} {value}")).map_err(sent_not_saved)?;
    }
    let mut names: Vec<&str> = order.iter().map(|(n, _)| n.as_str()).collect();
    if !a.non_interactive {
        clear_check_fault(s, ask).map_err(sent_not_saved)?;
        if jog_check(s, ask).map_err(sent_not_saved)? {
            names.push("dir");
        }
    }
    let saved = if a.no_save {
        "not saved (--no-save): the settings last until the board restarts".to_string()
    } else {
        save(s)?
    };
    // the summary is what the board holds after the last save, read back
    let (reply, now) = read_back(s)?;
    Ok(format!("{}\n{saved}", summary(&now, &held(&reply, &names))))
}

/// The lathe's top speed, held to what the cutter's drive can follow at
/// the board's ratio: asked again with that bound (or refused naming
/// `--max-lathe-rpm` and it), rather than every answer refused together
/// at the end. The reason is the board's own (`Config::with`).
fn top_speed_that_fits(f: Facts, current: &Config, a: &GuidedArgs, ask: &mut dyn Ask) -> CliResult<Facts> {
    let order = |rpm: u32| figures::send_order(current, &changes(&Facts { max_rpm: rpm, ..f.clone() }));
    let why = match order(f.max_rpm) {
        Ok(_) => return Ok(f),
        Err(e) => e.trim_start_matches("these settings do not fit together: ").to_string(),
    };
    if order(MAX_RPM.lo).is_err() {
        // not the speed: the stepper itself, or said as before when sent
        return no_speed_fits(&f, current, a).map_or(Ok(f), Err);
    }
    let lo = highest(MAX_RPM.lo, f.max_rpm, |rpm| order(rpm).is_ok());
    let at = format!("at the board's ratio {} ({why})", current.ratio);
    if a.non_interactive {
        return Err(CliError::flag("max-lathe-rpm", format!("must be <= {lo} rpm {at} (got {})", f.max_rpm)));
    }
    ask.say(&format!("{} rpm is too fast {at}: at most {lo} rpm", f.max_rpm));
    let max_rpm = ask.number("The lathe's fastest speed, rpm", Some(lo), MAX_RPM.lo, lo)?;
    Ok(Facts { max_rpm, ..f })
}

/// A stepper's `--start-rate` and STEP pulse against the step rate it
/// will have, by the board's own rules (`send_order`: `start-rate <=
/// max-rate`, `max-rate x 2 x pulse <= 1 s`): every flag at fault named in
/// one refusal, with its bound and the value given, rather than the first
/// rule the board trips. Each is judged with the other at its least, at
/// the slowest lathe (the speed's own bound is `top_speed_that_fits`').
fn within_the_step_rate(f: &Facts, current: &Config, a: &GuidedArgs) -> CliResult<()> {
    if f.bldc.is_some() {
        return Ok(());
    }
    let least = Facts { max_rpm: MAX_RPM.lo, start_rate: Some(START_RATE.lo), pulse_ns: Some(PULSE.lo), ..f.clone() };
    let fits = |g: Facts| figures::send_order(current, &changes(&g)).is_ok();
    if !fits(least.clone()) {
        return Ok(()); // not these two: the steps (`no_speed_fits`)
    }
    let max = stepper_max_rate(current);
    let mut faults = Vec::new();
    if let Some(r) = f.start_rate.filter(|&r| !fits(Facts { start_rate: Some(r), ..least.clone() })) {
        let most = highest(START_RATE.lo, r, |x| fits(Facts { start_rate: Some(x), ..least.clone() }));
        faults.push(format!("--start-rate must be at most {most} steps/s, the board's max-rate (got {r})"));
    }
    if let Some(p) = f.pulse_ns.filter(|&p| !fits(Facts { pulse_ns: Some(p), ..least.clone() })) {
        let most = highest(PULSE.lo, p, |x| fits(Facts { pulse_ns: Some(x), ..least.clone() }));
        faults.push(pulse_too_long(a, most, p, max));
    }
    match faults.is_empty() {
        true => Ok(()),
        false => Err(CliError(faults.join("; "))),
    }
}

/// A STEP pulse too long for the step rate, in the flag given: the
/// hidden `--pulse-us` in microseconds, with the nanoseconds it made.
fn pulse_too_long(a: &GuidedArgs, most: u32, ns: u32, max: u32) -> String {
    let why = format!("with the board's max-rate of {max} steps/s: a step is a pulse high and as long low");
    match a.pulse_us {
        Some(us) => format!("--pulse-us must be at most {} us {why} (got {us}, {ns} ns rounded up)", most as f64 / 1e3),
        None => format!("--pulse-ns must be at most {most} ns {why} (got {ns})"),
    }
}

/// The highest n in lo..hi that `fits`, where `fits(lo)` holds and
/// `fits(hi)` does not (a lower n fits wherever a higher one does).
fn highest(mut lo: u32, mut hi: u32, fits: impl Fn(u32) -> bool) -> u32 {
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        match fits(mid) {
            true => lo = mid,
            false => hi = mid,
        }
    }
    lo
}

/// A stepper no lathe speed fits, however slow: its steps a cutter turn
/// too many for the board's ratio and step rate, or its driver's pulse
/// too long for that rate. Refused naming what sets it and its bound,
/// found by the board's own rule (`send_order`); None when neither is at
/// fault (said as before, when the settings are sent).
fn no_speed_fits(f: &Facts, current: &Config, a: &GuidedArgs) -> Option<CliError> {
    if f.bldc.is_some() {
        return None; // a BLDC's rate follows its counts: the speed is at fault
    }
    let fits = |g: Facts| figures::send_order(current, &changes(&Facts { max_rpm: MAX_RPM.lo, ..g })).is_ok();
    if f.steps > 1 && fits(Facts { steps: 1, ..f.clone() }) {
        let most = highest(1, f.steps, |steps| fits(Facts { steps, ..f.clone() }));
        return Some(too_many_steps(f, current, a, most));
    }
    let pulse = f.pulse_ns.filter(|&p| p > PULSE.lo && fits(Facts { pulse_ns: Some(PULSE.lo), ..f.clone() }))?;
    let most = highest(PULSE.lo, pulse, |p| fits(Facts { pulse_ns: Some(p), ..f.clone() }));
    let why = format!(
        "with the board's max-rate of {} steps/s: a step is a pulse high and as long low (got {pulse})",
        stepper_max_rate(current)
    );
    Some(match a.non_interactive {
        true => CliError::flag("pulse-ns", format!("must be at most {most} ns {why}")),
        false => CliError(format!("setup: the driver's STEP pulse must be at most {most} ns {why}; nothing sent")),
    })
}

/// `no_speed_fits`' refusal of a stepper's steps a cutter turn: in the
/// flags that make them, or the interview's words.
fn too_many_steps(f: &Facts, current: &Config, a: &GuidedArgs, most: u32) -> CliError {
    let why =
        format!(
        "at the board's ratio {}: max-rpm x ratio x steps/60 must not exceed its max-rate of {} steps/s even at {} rpm",
        current.ratio, stepper_max_rate(current), MAX_RPM.lo
    );
    if !a.non_interactive {
        return CliError(format!(
            "setup: the motor's steps per cutter turn (full steps x microsteps x belt) must be at most {most} {why} (got {}); nothing sent",
            f.steps
        ));
    }
    let (full, micro) = (a.motor_steps.unwrap_or(MOTOR_STEPS), a.microsteps.unwrap_or(MICROSTEPS));
    let reduction = a.reduction.map_or("1".to_string(), |r| r.to_string());
    CliError(format!(
        "--motor-steps x --microsteps x --reduction must make at most {most} steps per cutter turn {why} (got {full} x {micro} x {reduction} = {})",
        f.steps
    ))
}

/// A board with a cam table fitted refuses another cutter under it (the
/// sync core's `changes_the_cutter`): said before anything is sent, not
/// half-way through the settings.
fn cam_keeps_its_cutter<P: Read + Write>(s: &mut Session<P>, current: &Config, next: &Config) -> CliResult<()> {
    if !polyturn_sync::controller::changes_the_cutter(current, next) {
        return Ok(());
    }
    let status = s.ask("status")?;
    match status.split_whitespace().any(|w| w.starts_with("cam=")) {
        true => Err(CliError(
            "setup: the board has a cam table fitted for its cutter, and these answers change the cutter (ratio, edges, dir or drive): polyturn device cam-off first (nothing sent)".into(),
        )),
        false => Ok(()),
    }
}

/// A setup stopped once its settings went to the board says so: the
/// board holds them until it restarts, none of them saved.
fn sent_not_saved(e: CliError) -> CliError {
    const SAID: &str = "(settings sent, not saved)";
    match e.0.contains(SAID) {
        true => e,
        false => CliError(format!(
            "{} {SAID}: `polyturn device get` shows what the board holds, a restart drops them",
            e.0.trim_end_matches(": nothing saved")
        )),
    }
}

/// The board's settings (`get`): its reply and what it says.
fn read_back<P: Read + Write>(s: &mut Session<P>) -> CliResult<(String, Config)> {
    let reply = s.ask("get")?;
    let c = figures::parse_settings(&reply)
        .ok_or_else(|| s.port_error("its settings could not be read (get): flash this version"))?;
    Ok((reply, c))
}

/// The values a `get` reply gives for `names`, each once, in their order.
fn held(reply: &str, names: &[&str]) -> Vec<(String, String)> {
    let all: Vec<(&str, &str)> = reply.split_whitespace().filter_map(|w| w.split_once('=')).collect();
    let mut out: Vec<(String, String)> = Vec::new();
    for n in names {
        if let Some((_, v)) = all.iter().find(|(k, _)| k == n).filter(|_| !out.iter().any(|(k, _)| k == n)) {
            out.push((n.to_string(), v.to_string()));
        }
    }
    out
}

/// `save`, waiting as long as a save takes. A `set` leaves a lathe at rest
/// at rest (`Controller::lathe_at_rest`), so a refusal here is real: the
/// board's reply says what it saw of the lathe.
fn save<P: Read + Write>(s: &mut Session<P>) -> CliResult<String> {
    ok_or_device_error(s.ask_within("save", super::FLASH_WAIT.max(s.timeout))?)
}

/// What can turn the cutter, in the order offered.
const CUTTERS: [&str; 3] = [
    "a stepper, or a servo taking step/dir",
    "a BLDC through a spindle driver's speed input (PWM, or 0-10 V through a filter)",
    "a BLDC through an RC ESC",
];

/// The questions, with the encoder check on the board.
fn interview<P: Read + Write>(s: &mut Session<P>, a: &GuidedArgs, ask: &mut dyn Ask) -> CliResult<Facts> {
    ask.say("polyturn setup: physical facts only; the board measures what it can.");
    let (cpr, moved) = lathe_encoder(s, a, ask)?;
    let bldc = match ask.choose("What turns the cutter?", &CUTTERS)? {
        0 => None,
        k => Some(drive::facts(ask, a, k == 2)?),
    };
    let steps = match &bldc {
        Some(b) => b.counts,
        None => motor_steps(ask, a)?,
    };
    let sense = match ask.choose("The cutter turns, against the chuck", &["same", "opposite"])? {
        0 => Sense::Same,
        _ => Sense::Opposite,
    };
    let max_rpm =
        ask.number("The lathe's fastest speed, rpm", a.max_lathe_rpm.or(Some(1500)), MAX_RPM.lo, MAX_RPM.hi)?;
    let f = Facts {
        cpr,
        steps,
        max_rpm,
        pulse_ns: None,
        dir_setup_ns: None,
        sense,
        encoder_reversed: moved < 0,
        motor_reversed: false,
        cutter_cpr: None,
        start_rate: None,
        bldc,
        after_bldc: false,
    };
    match f.bldc {
        Some(_) => Ok(f),
        None => stepper_driver(s, ask, a, f),
    }
}

/// The lathe's encoder: the check on the board, and its counts per turn
/// (measured, or from the label) and the way it counted.
fn lathe_encoder<P: Read + Write>(s: &mut Session<P>, a: &GuidedArgs, ask: &mut dyn Ask) -> CliResult<(u32, i64)> {
    let index = ask.yes("Does the lathe encoder have an index (Z) pulse wired to PB0?", true)?;
    let turns = if index { None } else { Some(ask.number("How many chuck turns will you make?", Some(3), 1, 20)?) };
    let (f, proposal) = checks::check_encoder(s, ask, Turning::UntilEnter, turns)?;
    ask.say(&checks::explain(&f, &proposal, turns));
    let cpr = match proposal {
        Ok(c) if ask.yes(&format!("Use cpr {c}?"), true)? => c,
        _ => {
            4 * ask.number("Encoder lines per turn, from its label", a.encoder_lines, CPR.lo.div_ceil(4), CPR.hi / 4)?
        }
    };
    Ok((cpr, f.moved))
}

/// A stepper's steps per cutter turn: the motor, the driver, the belt;
/// asked again while they make no whole number the console takes.
fn motor_steps(ask: &mut dyn Ask, a: &GuidedArgs) -> CliResult<u32> {
    retry(ask, |ask| {
        let full = ask.number("Motor full steps per turn", Some(a.motor_steps.unwrap_or(MOTOR_STEPS)), 1, 100_000)?;
        let micro = ask.number("Driver microsteps", Some(a.microsteps.unwrap_or(MICROSTEPS)), 1, 512)?;
        let belt = ask.choose("Between motor and cutter", &["direct", "belt or gears"])?;
        let reduction = if belt == 0 {
            (1, 1)
        } else {
            (
                ask.number("Cutter pulley teeth", None, 1, 1000)? as u64,
                ask.number("Motor pulley teeth", None, 1, 1000)? as u64,
            )
        };
        figures::steps_per_cutter_turn(full, micro, reduction).map_err(CliError)
    })
}

/// A stepper's driver timing, its shaft encoder and its start rate.
fn stepper_driver<P: Read + Write>(
    s: &mut Session<P>,
    ask: &mut dyn Ask,
    a: &GuidedArgs,
    f: Facts,
) -> CliResult<Facts> {
    // within what the board's max-rate allows (a step is a pulse high and
    // as long low), asked again there rather than refused after the rest
    let rate = stepper_max_rate(&read_back(s)?.1);
    let most = (1_000_000_000 / (2 * u64::from(rate)).max(1)).clamp(u64::from(PULSE.lo), u64::from(PULSE.hi)) as u32;
    let q = format!(
        "The driver's shortest STEP pulse, ns (its datasheet; 2500 if unsure; at most {most} at the board's max-rate of {rate} steps/s)"
    );
    let pulse_ns = Some(ask.number(&q, Some(2500.min(most)), PULSE.lo, most)?);
    let q = "The driver's DIR setup time, ns (5000 if unsure)";
    let dir_setup_ns = Some(ask.number(q, Some(5000), DIR_SETUP.lo, DIR_SETUP.hi)?);
    let cutter_cpr = Some(shaft_encoder(ask, a)?);
    Ok(Facts { pulse_ns, dir_setup_ns, cutter_cpr, start_rate: Some(start_rate(s, ask, a)?), ..f })
}

/// The lost-step alarm's encoder, if there is one: its counts per cutter
/// turn, 0 for none.
fn shaft_encoder(ask: &mut dyn Ask, a: &GuidedArgs) -> CliResult<u32> {
    let q = "Is there an encoder on the motor's shaft or the cutter spindle, wired to PB6/PB7 (the lost-step alarm)?";
    if !ask.yes(q, a.cutter_encoder_cpr.is_some_and(|n| n != 0))? {
        return Ok(0);
    }
    let q = "Its counts per cutter turn (4 x lines x belt)";
    ask.number(q, a.cutter_encoder_cpr.filter(|&n| n != 0), CUTTER_CPR.lo, CUTTER_CPR.hi)
}

/// The motor's start rate, up to the stepper's `max-rate` (the rule the
/// board holds it to): 0, off, unless the machinist has found it.
fn start_rate<P: Read + Write>(s: &mut Session<P>, ask: &mut dyn Ask, a: &GuidedArgs) -> CliResult<u32> {
    let max = stepper_max_rate(&read_back(s)?.1).min(START_RATE.hi);
    let q = "The motor's start rate with the cutter fitted, steps/s: engaged at rest, the cutter then starts at the lathe's speed (0 if unsure: every change ramps; find it on the bench)";
    ask.number(q, Some(a.start_rate.unwrap_or(0).min(max)), START_RATE.lo, max)
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
/// True if `dir` was flipped.
fn jog_check<P: Read + Write>(s: &mut Session<P>, ask: &mut dyn Ask) -> CliResult<bool> {
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
        return Ok(true);
    }
    Ok(false)
}

#[cfg(test)]
#[path = "setup_tests.rs"]
mod tests;
