//! `polyturn device check-encoder` and `jog`: the board's checks, with the
//! machinist's part asked for and the result explained.

use super::figures::{self, EncoderFigures};
use super::prompt::Ask;
use super::session::Session;
use crate::cli::errors::{CliError, CliResult};
use std::io::{Read, Write};
use std::time::{Duration, Instant};

/// The board's hands-off window (`controller::checks::STILL_SECONDS`),
/// with a margin for the USB round trip.
const STILL: Duration = Duration::from_millis(1_300);

/// How the machinist turns the chuck: by hand until Enter, or (scripts)
/// for a set time with the lathe running slowly.
#[derive(Clone, Copy, Debug)]
pub enum Turning {
    UntilEnter,
    For(Duration),
}

/// Runs the encoder check; returns the figures and the cpr proposal (or
/// why there is none).
pub fn check_encoder<P: Read + Write>(
    s: &mut Session<P>,
    ask: &mut dyn Ask,
    turning: Turning,
    turns: Option<u32>,
) -> CliResult<(EncoderFigures, Result<u32, String>)> {
    s.ask("check-encoder start")?;
    ask.say("Encoder check: hands off the chuck for a second...");
    // from here the board's check runs: a Ctrl-C anywhere stops it
    if !pause(STILL) {
        return Err(stopped(s, ask.interrupted()));
    }
    match turning {
        Turning::UntilEnter => {
            let what = match turns {
                Some(n) => format!("Turn the chuck FORWARD by hand exactly {n} turn(s) from a mark, then press Enter"),
                None => "Turn the chuck FORWARD by hand 3 turns or more, one way only, then press Enter".into(),
            };
            if let Err(e) = ask.wait(&what) {
                return Err(stopped(s, e));
            }
        }
        Turning::For(d) => {
            ask.say(&format!("Measuring for {:.1} s: run the lathe slowly forward", d.as_secs_f64()));
            if !pause(d) {
                return Err(stopped(s, ask.interrupted()));
            }
        }
    }
    let reply = s.ask("check-encoder stop")?;
    let f = figures::parse_encoder(&reply)
        .ok_or_else(|| s.port_error(format!("unexpected reply to check-encoder stop: '{reply}'")))?;
    let proposal = figures::propose_cpr(&f, turns);
    Ok((f, proposal))
}

/// Waits `d`, or until Ctrl-C (false).
fn pause(d: Duration) -> bool {
    let end = Instant::now() + d;
    while !super::prompt::cancelled_by_ctrl_c() {
        let now = Instant::now();
        if now >= end {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20).min(end - now));
    }
    false
}

/// A check cut short: the board's check stopped too (else engage, jog and
/// divide stay refused), and the error says whether it could be.
fn stopped<P: Read + Write>(s: &mut Session<P>, e: CliError) -> CliError {
    match s.ask("check-encoder stop") {
        Ok(_) => CliError(format!("{} (the board's encoder check stopped)", e.0)),
        Err(stop) => CliError(format!(
            "{} (the board's encoder check may still run: {}; `polyturn device check-encoder --seconds 0.1` ends it)",
            e.0, stop.0
        )),
    }
}

/// The check's result in words, with what to do; `turns` as given.
pub fn explain(f: &EncoderFigures, proposal: &Result<u32, String>, turns: Option<u32>) -> String {
    let mut out = vec![format!(
        "counts: {} ({} against the direction of travel), index pulses: {}, chatter at rest: {}, jumps: {}",
        f.moved, f.backward, f.indexes, f.chatter, f.jumps
    )];
    if let Some((lo, hi)) = f.gap {
        out.push(format!("counts between index pulses: {lo}..{hi}"));
    }
    if f.moved < 0 {
        out.push("the counts FELL while you turned forward: swap the A and B wires, or let `polyturn device setup` set dir for it".into());
    }
    if f.chatter > 0 {
        out.push("the count changed while the chuck was still: an encoder edge sitting on a line, or noise (shielded cable, common ground)".into());
    }
    out.extend(figures::disagreement(f, turns));
    out.push(match proposal {
        Ok(c) => format!("proposed: set cpr {c}   (polyturn device set cpr {c})"),
        Err(why) => format!("no cpr proposed: {why}"),
    });
    out.join("\n")
}

/// The longest self-test plan waited for, s (the board's is about 11 s
/// at 400 rpm, and longer only at slow speeds).
const SELFTEST_MAX_S: f64 = 600.0;

/// Runs the bench self-test: starts it with `start` (`selftest start
/// [rpm]`), asks for its figures every 250 ms until it ends, at most its
/// length and 5 s; `Ok` only for a pass, a fail is an error with the board's
/// reason and figures.
pub fn selftest<P: Read + Write>(s: &mut Session<P>, start: &str) -> CliResult<String> {
    let started = super::session::ok_or_device_error(s.ask(start)?)?;
    let seconds = started
        .split_whitespace()
        .find_map(|w| w.strip_prefix("seconds="))
        .and_then(|v| v.trim_end_matches(':').parse::<f64>().ok())
        // the board's plan is tens of seconds: anything else (`1e308`, `inf`,
        // `-1` from a port that is not one) must not become the wait
        .filter(|s| (0.0..=SELFTEST_MAX_S).contains(s))
        .unwrap_or(60.0);
    let limit = Duration::from_secs_f64(seconds + 5.0);
    let begun = Instant::now();
    loop {
        std::thread::sleep(Duration::from_millis(250));
        let r = s.ask("selftest")?;
        if r.starts_with("ok selftest pass") {
            return Ok(format!("{started}\n{r}"));
        }
        if r.starts_with("ok selftest fail") {
            return Err(CliError(format!(
                "device: the self-test failed: {}",
                r.trim_start_matches("ok selftest fail: ")
            )));
        }
        if !r.starts_with("ok selftest running") {
            return Err(CliError(format!("device: unexpected reply during the self-test: {r}")));
        }
        if begun.elapsed() > limit {
            let _ = s.ask("selftest stop");
            return Err(s.port_error(format!("the self-test did not end within {:.0} s: stopped", limit.as_secs_f64())));
        }
    }
}

/// Sends `jog DEG` and waits (bounded) until the board is idle again.
pub fn jog<P: Read + Write>(s: &mut Session<P>, degrees: &str) -> CliResult<String> {
    // checked before sending, with the console's own parser and bound: the
    // wait below is made from it, whatever the port answers
    let mdeg = jog_mdeg(degrees)?;
    let reply = s.ask(&format!("jog {degrees}"))?;
    // 2 s a cutter turn at most (`JOG_SECONDS_PER_TURN`), plus the ramps
    let limit = Duration::from_millis(u64::from(mdeg.unsigned_abs()) / 180 + 5_000);
    let start = Instant::now();
    loop {
        std::thread::sleep(Duration::from_millis(100));
        let status = s.ask("status")?;
        if !status.starts_with("ok state=jogging") {
            if status.starts_with("ok state=idle") {
                return Ok(format!("{reply}\ndone: the cutter has stopped"));
            }
            return Err(CliError(format!("device: the jog ended in {}", status.trim_start_matches("ok "))));
        }
        if start.elapsed() > limit {
            let _ = s.ask("stop");
            return Err(s.port_error(format!("the jog did not end within {:.0} s: stopped", limit.as_secs_f64())));
        }
    }
}

/// `jog`'s angle as the console takes it (`console::checks::parse_jog`:
/// its parser and `JOG_MAX_MDEG`), in millidegrees.
fn jog_mdeg(degrees: &str) -> CliResult<i32> {
    let max = polyturn_sync::controller::jog::JOG_MAX_MDEG;
    polyturn_sync::config::degrees_mdeg(degrees, max)
        .ok_or_else(|| CliError(format!("DEGREES {} (got '{}')", jog_range(max), crate::cli::errors::escaped(degrees))))
}

fn jog_range(max_mdeg: i32) -> String {
    format!("must be {}..={} degrees of the cutter, up to 3 decimals", -max_mdeg / 1000, max_mdeg / 1000)
}

/// clap's check of `polyturn device jog DEGREES`: refused before the port
/// opens, in the console's own syntax and range.
pub fn jog_degrees(s: &str) -> Result<String, String> {
    let max = polyturn_sync::controller::jog::JOG_MAX_MDEG;
    match polyturn_sync::config::degrees_mdeg(s, max) {
        Some(_) => Ok(s.to_string()),
        None => Err(jog_range(max)),
    }
}
