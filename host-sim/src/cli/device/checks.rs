//! `polyturn device check-encoder` and `jog`: the board's checks, with the
//! machinist's part asked for and the result explained (issue 14).

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
    std::thread::sleep(STILL);
    match turning {
        Turning::UntilEnter => {
            let what = match turns {
                Some(n) => format!("Turn the chuck FORWARD by hand exactly {n} turn(s) from a mark, then press Enter"),
                None => "Turn the chuck FORWARD by hand 3 turns or more, one way only, then press Enter".into(),
            };
            ask.wait(&what)?;
        }
        Turning::For(d) => {
            ask.say(&format!("Measuring for {:.1} s: run the lathe slowly forward", d.as_secs_f64()));
            std::thread::sleep(d);
        }
    }
    let reply = s.ask("check-encoder stop")?;
    let f = figures::parse_encoder(&reply)
        .ok_or_else(|| s.port_error(format!("unexpected reply to check-encoder stop: '{reply}'")))?;
    let proposal = figures::propose_cpr(&f, turns);
    Ok((f, proposal))
}

/// The check's result in words, with what to do.
pub fn explain(f: &EncoderFigures, proposal: &Result<u32, String>) -> String {
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
    out.push(match proposal {
        Ok(c) => format!("proposed: set cpr {c}   (polyturn device set cpr {c})"),
        Err(why) => format!("no cpr proposed: {why}"),
    });
    out.join("\n")
}

/// Sends `jog DEG` and waits (bounded) until the board is idle again.
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

pub fn jog<P: Read + Write>(s: &mut Session<P>, mdeg_text: &str) -> CliResult<String> {
    let reply = s.ask(&format!("jog {mdeg_text}"))?;
    let deg: f64 = mdeg_text.parse().unwrap_or(3600.0);
    // 2 s a cutter turn at most (`JOG_SECONDS_PER_TURN`), plus the ramps
    let limit = Duration::from_secs_f64(deg.abs() / 360.0 * 2.0 + 5.0);
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
