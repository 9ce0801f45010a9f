//! The setup checks' commands: `check-encoder`, `jog` and
//! `dfu`. Replies are one line of `name=value` figures that a machinist
//! reads and `polyturn device` parses.

use super::{Command, Outcome, Reply};
use crate::check::EncoderReport;
use crate::controller::jog::JOG_MAX_MDEG;
use crate::controller::{Controller, JogPlan};
use core::fmt::Write;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EncoderOp {
    Start,
    Report,
    Stop,
}

pub const JOG_USAGE: &str = "usage: jog <degrees of the cutter, -3600..=3600, up to 3 decimals>";
pub const DFU_REPLY: &str =
    "ok restarting into the ROM DFU bootloader (USB 0483:df11): write the image with polyturn flash";
const NOT_RUNNING: &str = "no encoder check running: send check-encoder start";
const STARTED: &str = "ok encoder check started: hands off the chuck for 1 s, then turn it forward by hand 3 turns or more, one way only; check-encoder shows the figures";

pub(super) fn parse_encoder(op: Option<&str>) -> Command<'static> {
    match op {
        None => Command::CheckEncoder(EncoderOp::Report),
        Some("start") => Command::CheckEncoder(EncoderOp::Start),
        Some("stop") => Command::CheckEncoder(EncoderOp::Stop),
        Some(_) => Command::Bad("usage: check-encoder [start|stop]"),
    }
}

pub(super) fn parse_jog(deg: &str) -> Command<'static> {
    match crate::config::degrees_mdeg(deg, JOG_MAX_MDEG) {
        Some(mdeg) => Command::Jog(mdeg),
        None => Command::Bad(JOG_USAGE),
    }
}

pub(super) fn encoder(op: EncoderOp, ctl: &mut Controller) -> Outcome {
    let report = match op {
        EncoderOp::Start => {
            return match ctl.start_encoder_check() {
                Ok(()) => Outcome::Text(STARTED),
                Err(r) => Outcome::Error(r.describe()),
            }
        }
        EncoderOp::Report => ctl.encoder_check(),
        EncoderOp::Stop => ctl.stop_encoder_check(),
    };
    match report {
        Some(r) => Outcome::Encoder(r, op),
        None => Outcome::Error(NOT_RUNNING),
    }
}

/// `ok encoder [ended] moved=.. backward=.. jumps=.. chatter=.. still=..
/// indexes=.. skipped=.. gaps=.. gap=min..max cpr=..|none`
pub(super) fn write_encoder(r: &EncoderReport, op: EncoderOp, out: &mut Reply) {
    let ended = if op == EncoderOp::Stop { " ended" } else { "" };
    let still = if r.still_done { "done" } else { "measuring" };
    let _ = write!(
        out,
        "ok encoder{ended} moved={} backward={} jumps={} chatter={} still={still} indexes={} skipped={}",
        r.moved, r.backward, r.jumps, r.chatter, r.indexes, r.skipped
    );
    match r.gap {
        Some((n, lo, hi)) => {
            let _ = write!(out, " gaps={n} gap={lo}..{hi}");
        }
        None => {
            let _ = out.push_str(" gaps=0 gap=none");
        }
    }
    let _ = match r.cpr {
        Some(c) => write!(out, " cpr={c}"),
        None => write!(out, " cpr=none"),
    };
}

/// `ok jogging steps=.. deg=.. rate_hz=..`
pub(super) fn write_jog(plan: &JogPlan, mdeg: i32, out: &mut Reply) {
    let sign = if mdeg < 0 { "-" } else { "" };
    let m = mdeg.unsigned_abs();
    let _ =
        write!(out, "ok jogging steps={} deg={sign}{}.{:03} rate_hz={}", plan.steps, m / 1000, m % 1000, plan.rate_hz);
}
