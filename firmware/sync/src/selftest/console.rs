//! `selftest [start [rpm]|stop]`: the bench self-test's console commands
//! (`console::selftest`, kept here with the rest of the self-test).
//! One reply line of `name=value` figures; a failed test is reported as
//! such (`ok selftest fail ...`: the command worked, the board did not).

use super::status::Milli;
use super::{Command, Outcome, Reply};
use crate::controller::selftest::SelfTestRefusal;
use crate::controller::{Controller, Refusal};
use crate::selftest::{Failure, Kind, Plan, Report, Verdict};
use core::fmt::Write;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SelfTestOp {
    Start(Option<u32>),
    Report,
    Stop,
}

pub const USAGE: &str = "usage: selftest [start [rpm]|stop]";
const NONE_RUN: &str = "no self-test has run: send selftest start";

pub(super) fn parse(op: Option<&str>, rpm: Option<&str>) -> Command<'static> {
    match (op, rpm) {
        (None, None) => Command::SelfTest(SelfTestOp::Report),
        (Some("stop"), None) => Command::SelfTest(SelfTestOp::Stop),
        (Some("start"), None) => Command::SelfTest(SelfTestOp::Start(None)),
        (Some("start"), Some(r)) => match super::number::unsigned(r) {
            Some(n) if r.len() <= 6 => Command::SelfTest(SelfTestOp::Start(Some(n))),
            _ => Command::Bad("selftest start rpm: a whole number of lathe rpm (see selftest start's limits)"),
        },
        _ => Command::Bad(USAGE),
    }
}

/// A plan made outside the lock (`console::prepare`), with the settings'
/// generation it was made for.
type Planned = (u32, Result<Plan, SelfTestRefusal>);

/// `selftest start` (with its `planned` run), `selftest` and `selftest stop`.
pub(super) fn apply(op: SelfTestOp, planned: Option<Planned>, ctl: &mut Controller) -> Outcome {
    let report = match (op, planned) {
        (SelfTestOp::Start(_), None) => return Outcome::Error("internal: command not prepared"),
        (SelfTestOp::Start(_), Some((g, _))) if g != ctl.config_generation() => {
            return Outcome::Error("the settings changed meanwhile: nothing changed, send it again")
        }
        (SelfTestOp::Start(_), Some((_, plan))) => {
            return match plan.and_then(|p| ctl.start_selftest_planned(p).map(|()| p)) {
                Ok(p) => Outcome::SelfTestStarted(p.rpm, p.cpr, p.total_ms()),
                Err(r) => Outcome::SelfTestRefused(r),
            }
        }
        (SelfTestOp::Report, _) => ctl.selftest_report(),
        (SelfTestOp::Stop, _) => ctl.stop_selftest(),
    };
    match report {
        Some(r) => Outcome::SelfTest(r),
        None => Outcome::Error(NONE_RUN),
    }
}

pub(super) fn write_started(rpm: u32, cpr: u32, ms: u32, out: &mut Reply) {
    let _ = write!(
        out,
        "ok selftest started rpm={} cpr={} seconds={}.{}: jumpers PA2-PA6, PA3-PA7, PA4-PB0 and PB14 to GND; the cutter turns; selftest shows the figures",
        rpm,
        cpr,
        ms / 1000,
        ms % 1000 / 100
    );
}

pub(super) fn write_refused(r: SelfTestRefusal, out: &mut Reply) {
    let _ = match r {
        SelfTestRefusal::NotIdle => {
            write!(out, "error: stop first (and clear any fault): the self-test engages the gearbox")
        }
        SelfTestRefusal::LatheTurning => {
            write!(out, "error: the lathe input is moving: unplug the lathe encoder, then wire the self-test's jumpers")
        }
        SelfTestRefusal::NoCutter => write!(out, "error: drive=none: there is no cutter to test"),
        SelfTestRefusal::NotStepper => {
            write!(out, "error: drive=bldc: the self-test checks the step output; set drive stepper for the bench")
        }
        SelfTestRefusal::CamFitted => {
            write!(out, "error: a cam table is fitted and the X axis would follow the test: cam off first")
        }
        SelfTestRefusal::Cpr(c) => write!(out, "error: cpr {c}: the self-test needs an even cpr, 4 or more"),
        SelfTestRefusal::Rpm { max: 0 } => write!(out, "error: selftest start rpm: no speed fits max-rpm and max-rate"),
        SelfTestRefusal::Rpm { max } => {
            write!(out, "error: selftest start rpm: 1..={max} (the generator, max-rpm and max-rate allow)")
        }
        SelfTestRefusal::Checking => {
            write!(
                out,
                "error: an encoder check is running: check-encoder stop first, then wire the self-test's jumpers"
            )
        }
        SelfTestRefusal::Dividing => write!(out, "error: {}", Refusal::Dividing.describe()),
    };
}

/// `ok selftest running|pass|fail ...`
pub(super) fn write_report(r: &Report, out: &mut Reply) {
    let _ = match r.verdict {
        Verdict::Running => write!(
            out,
            "ok selftest running t={}.{}/{}.{} leg={} rests={}/3",
            r.at_ms / 1000,
            r.at_ms % 1000 / 100,
            r.total_ms / 1000,
            r.total_ms % 1000 / 100,
            leg_name(r.leg),
            r.rests
        ),
        Verdict::Pass => write!(out, "ok selftest pass"),
        Verdict::Fail(f) => {
            let _ = write!(out, "ok selftest fail: ");
            write_failure(f, out)
        }
    };
    let [(s1, t1), (s2, t2)] = r.holds;
    let _ = write!(
        out,
        " rpm={} forward={} backward={} indexes={} lag_steps={},{} hold_steps={s1}/{t1},{s2}/{t2} index_latency_cycles={}",
        r.rpm,
        r.forward,
        r.backward,
        r.indexes,
        Milli::steps_q16(r.hold_lag_q16),
        Milli::steps_q16(r.ramp_lag_q16),
        r.latency_cycles,
    );
}

fn leg_name(k: Kind) -> &'static str {
    match k {
        Kind::Rest => "rest",
        Kind::Ramp => "ramp",
        Kind::Hold => "hold",
    }
}

fn write_failure(f: Failure, out: &mut Reply) -> core::fmt::Result {
    match f {
        Failure::Fault(x) => write!(out, "fault {}: {};", x.name(), x.reason()),
        Failure::Stopped => write!(out, "stopped before the end;"),
        Failure::Generator => write!(out, "the generator stopped early (TIM9): a firmware fault, please report it;"),
        Failure::NotSynced { rest } => {
            write!(out, "rest {rest}: the cutter did not reach the target at rest: check max-rate and max-accel;")
        }
        Failure::Counts { rest, seen, made } => {
            write!(out, "rest {rest}: counted {seen}, generated {made}: ")?;
            let hint = if seen == 0 {
                "no counts: jumper PA2 to PA6 and PA3 to PA7"
            } else if seen == -made {
                "counting backward: PA2 and PA3 swapped"
            } else {
                "counts lost or doubled: shorter jumpers, and see the README's self-test timing"
            };
            write!(out, "{hint};")
        }
        Failure::Indexes { rest, seen, made } => {
            write!(out, "rest {rest}: index pulses seen {seen}, made {made}: jumper PA4 to PB0;")
        }
        Failure::IndexLate { rest, seen, made } => write!(
            out,
            "rest {rest}: the index latched count {seen}, made at {made}: the generator's interrupt was late, see the README's self-test timing;"
        ),
        Failure::Gear { rest, target, exact } => {
            write!(out, "rest {rest}: gear target {target}, exact {exact}: a firmware fault, please report it;")
        }
        Failure::Cutter { rest, off_q16 } => write!(
            out,
            "rest {rest}: the cutter stands {} steps from the exact target: steps lost, please report it;",
            Milli::steps_q16(off_q16)
        ),
    }
}

#[cfg(test)]
#[path = "console_tests.rs"]
mod tests;
