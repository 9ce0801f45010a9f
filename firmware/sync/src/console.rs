//! The console protocol: one line in, one line out (`ok ...` or
//! `error: ...`), no allocation. Used by the firmware's USB console, by
//! `polyturn device` and by tests. Any bytes get an answer; an error never
//! changes a setting.

use crate::config::{Config, DriveKind, Misfit, Sense, SetError, NAMES};
use crate::controller::{Controller, PreparedConfig, Refusal};
use crate::timing::Timing;
use core::fmt::Write;

mod checks;
mod divide;
mod misfit;
pub mod number;
// the self-test's commands, with the rest of the self-test (`crate::selftest`)
#[path = "selftest/console.rs"]
mod selftest;
mod status;

pub use divide::DivideOp;
pub use selftest::SelfTestOp;

/// Longest reply line: with its tag (`#`, `tag::TAG_DIGITS` digits and a
/// space) within the 512 bytes `polyturn device` takes as a line.
pub const REPLY_LEN: usize = 512 - (tag::TAG_DIGITS + 2);
pub type Reply = heapless::String<REPLY_LEN>;

/// What the firmware must do besides sending the reply.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Action {
    None,
    /// write the settings to flash (only ever returned while idle)
    Save,
    /// stream `status` lines until the next input
    Watch,
    /// restart into the ROM's USB DFU bootloader once the reply is out
    /// (only ever returned while idle)
    Dfu,
}

pub use status::{cam_wait, write_status as status_line, CamWait, LatheSeen, Snapshot};

pub const HELP: &str = "ok commands: get [name] | set <name> <value> | engage | stop | status | watch | save | defaults | clear | cam begin|data|end|off | check-encoder [start|stop] | jog <deg> | selftest [start [rpm]|stop] | divide <divisions>|stop | dfu | help; names: cpr steps ratio dir edges max-rate max-accel ferror phase drive dir-setup pulse enable max-rpm cutter-cpr lost-steps start-rate bldc-out pwm-hz bldc-tau";

/// A parsed command line (no controller needed: parse outside any lock).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command<'a> {
    Help,
    GetAll,
    Get(&'static str),
    Set(&'a str, &'a str),
    Engage,
    Stop,
    Clear,
    Status,
    Watch,
    Save,
    Defaults,
    /// `check-encoder start|stop`, or the figures so far
    CheckEncoder(checks::EncoderOp),
    /// cutter millidegrees
    Jog(i32),
    /// `selftest start [rpm]|stop`, or the figures so far
    SelfTest(SelfTestOp),
    /// `divide <divisions>|stop`, or the readout
    Divide(DivideOp),
    Dfu,
    Bad(&'static str),
}

/// What applying a command did: copies only, so the reply is rendered
/// after the controller's lock is released (the tick shares that lock).
#[derive(Clone, Copy, Debug)]
pub enum Outcome {
    Text(&'static str),
    Error(&'static str),
    FieldError(&'static str, &'static str),
    /// a `set` valid alone that does not fit with the others: its bound
    /// is worked out when the reply is written
    Misfit(Misfit),
    Value(Config, &'static str),
    All(Config),
    State(&'static str),
    Status(Snapshot),
    Watch(Snapshot),
    Save,
    Encoder(crate::check::EncoderReport, checks::EncoderOp),
    Jog(crate::controller::JogPlan, i32),
    /// rpm, cpr and length (ms) of the test started
    SelfTestStarted(u32, u32, u32),
    SelfTestRefused(crate::controller::selftest::SelfTestRefusal),
    SelfTest(crate::selftest::Report),
    /// the dividing readout
    Divide(Snapshot),
    Dfu,
    /// `save` or `jog` refused with the lathe turning: what the board saw,
    /// and what waits for the lathe to stop
    LatheTurning(status::LatheSeen, &'static str),
}

pub fn parse(line: &[u8]) -> Command<'_> {
    let Ok(text) = core::str::from_utf8(line) else {
        return Command::Bad("not text: commands are plain ASCII (try help)");
    };
    let mut words = text.split_ascii_whitespace();
    let cmd = words.next().unwrap_or("");
    let (a, b, extra) = (words.next(), words.next(), words.next());
    match (cmd, a, b, extra) {
        ("help" | "?", None, ..) => Command::Help,
        ("get", None, ..) => Command::GetAll,
        ("get", Some(name), None, _) => match NAMES.iter().find(|n| **n == name) {
            Some(n) => Command::Get(n),
            None => Command::Bad("get: unknown name (try help)"),
        },
        ("set", Some(name), Some(value), None) => Command::Set(name, value),
        ("set", ..) => Command::Bad("usage: set <name> <value>"),
        ("engage", None, ..) => Command::Engage,
        ("stop", None, ..) => Command::Stop,
        ("clear", None, ..) => Command::Clear,
        ("status", None, ..) => Command::Status,
        ("watch", None, ..) => Command::Watch,
        ("save", None, ..) => Command::Save,
        ("defaults", None, ..) => Command::Defaults,
        ("check-encoder", op, None, _) => checks::parse_encoder(op),
        ("jog", Some(deg), None, _) => checks::parse_jog(deg),
        ("jog", ..) => Command::Bad(checks::JOG_USAGE),
        ("selftest", op, rpm, None) => selftest::parse(op, rpm),
        ("selftest", ..) => Command::Bad(selftest::USAGE),
        ("divide", n, None, _) => divide::parse(n),
        ("divide", ..) => Command::Bad(divide::USAGE),
        ("dfu", None, ..) => Command::Dfu,
        ("", ..) => Command::Bad("empty line (try help)"),
        _ => Command::Bad("unknown command or wrong arguments (try help)"),
    }
}

/// The settings a `set` or `defaults` would install, derived before the
/// controller's lock is taken (`Derived::new` is the long part).
#[derive(Clone, Copy, Debug)]
pub struct Prepared {
    /// the settings' generation it was derived from: the lock checks it
    /// still holds (`Controller::config_generation`)
    generation: u32,
    next: Result<PreparedConfig, SetError>,
    /// `selftest start`'s plan (it divides in 128 bits: not under the lock)
    selftest: Option<Result<crate::selftest::Plan, crate::controller::selftest::SelfTestRefusal>>,
    /// the setting a `set` names, as `NAMES` spells it, and whether it is
    /// the phase (looked up here: string compares are not for the lock)
    setting: &'static str,
    phase: bool,
}

/// The long half of `apply`, outside the lock: `current` and `generation`
/// are short copies taken from the controller.
pub fn prepare(cmd: &Command<'_>, current: Config, generation: u32, timing: Timing) -> Option<Prepared> {
    let setting = match *cmd {
        Command::Set(name, _) => NAMES.iter().find(|n| **n == name).copied().unwrap_or("name"),
        _ => "",
    };
    let phase = setting == "phase";
    let next = match *cmd {
        Command::Set(name, value) => current.try_with(name, value),
        Command::Defaults => Ok(Config::default()),
        Command::SelfTest(SelfTestOp::Start(rpm)) => {
            let p = PreparedConfig::prepare(current, &current, timing);
            let plan = crate::controller::selftest::plan_selftest(&current, p.derived(), rpm);
            return Some(Prepared { generation, next: Ok(p), selftest: Some(plan), setting, phase });
        }
        _ => return None,
    };
    let next = next.map(|c| PreparedConfig::prepare(c, &current, timing));
    Some(Prepared { generation, next, selftest: None, setting, phase })
}

/// Applies a command to the controller (on the host, in one go).
pub fn apply(cmd: Command<'_>, ctl: &mut Controller) -> Outcome {
    let pre = prepare(&cmd, *ctl.config(), ctl.config_generation(), ctl.timing());
    apply_prepared(cmd, pre.as_ref(), ctl)
}

/// Why `apply_prepared` installed nothing: said as (field, text), or the
/// prepared misfit (by reference: it holds a copy of the settings).
enum NotInstalled<'a> {
    Said(Option<&'static str>, &'static str),
    Misfit(&'a Misfit),
}

impl From<Refusal> for NotInstalled<'_> {
    fn from(r: Refusal) -> Self {
        NotInstalled::Said(None, r.describe())
    }
}

fn refused(why: NotInstalled<'_>) -> Outcome {
    match why {
        NotInstalled::Said(Some(f), text) => Outcome::FieldError(f, text),
        NotInstalled::Said(None, text) => Outcome::Error(text),
        NotInstalled::Misfit(m) => Outcome::Misfit(*m),
    }
}

/// Applies a command prepared by `prepare`: short, no formatting, no
/// derivation (the firmware holds the tick's lock for this only), and
/// `pre` by reference: the settings and their figures are copied once,
/// into the controller, where they change.
pub fn apply_prepared(cmd: Command<'_>, pre: Option<&Prepared>, ctl: &mut Controller) -> Outcome {
    // (the error as (field, text), not an `Outcome`: a small Err keeps
    // the Result small; `Outcome` carries a whole status snapshot)
    let installed = |ctl: &mut Controller, phase: bool| -> Result<Config, NotInstalled<'_>> {
        let Some(p) = pre else { return Err(NotInstalled::Said(None, "internal: command not prepared")) };
        if p.generation != ctl.config_generation() {
            return Err(NotInstalled::Said(None, "the settings changed meanwhile: nothing changed, send it again"));
        }
        if p.next.is_err() {
            // engaged, "stop first" comes before how the value fits
            ctl.settings_may_change(phase)?;
        }
        let next = p.next.as_ref().map_err(|e| match e {
            SetError::Alone(e) => NotInstalled::Said(Some(e.field), e.allowed),
            SetError::Together(m) => NotInstalled::Misfit(m),
        })?;
        ctl.install_config(next)?;
        Ok(*next.config())
    };
    match cmd {
        Command::Help => Outcome::Text(HELP),
        Command::Bad(msg) => Outcome::Error(msg),
        Command::GetAll => Outcome::All(*ctl.config()),
        Command::Get(name) => Outcome::Value(*ctl.config(), name),
        Command::Set(..) => match installed(ctl, pre.is_some_and(|p| p.phase)) {
            Ok(c) => Outcome::Value(c, pre.map_or("name", |p| p.setting)),
            Err(e) => refused(e),
        },
        Command::Engage => match ctl.engage() {
            Ok(()) => Outcome::Text("ok engaging"),
            Err(r) => Outcome::Error(r.describe()),
        },
        Command::Stop => {
            ctl.disengage();
            Outcome::Text("ok stopping")
        }
        Command::Clear => {
            ctl.clear();
            Outcome::State(ctl.state().name())
        }
        Command::Status => Outcome::Status(Snapshot::of(ctl)),
        Command::Watch => Outcome::Watch(Snapshot::of(ctl)),
        Command::Save if ctl.state() != crate::state::State::Idle => {
            Outcome::Error("stop first: settings are saved only while idle")
        }
        Command::Save if !ctl.lathe_at_rest() => {
            Outcome::LatheTurning(status::LatheSeen::of(ctl), "saving pauses the controller for up to 2 s")
        }
        Command::Save => Outcome::Save,
        Command::Defaults => match installed(ctl, false) {
            Ok(_) => Outcome::Text("ok defaults loaded (not saved: use save)"),
            Err(e) => refused(e),
        },
        Command::CheckEncoder(op) => checks::encoder(op, ctl),
        Command::Jog(mdeg) => match ctl.jog(mdeg) {
            Ok(plan) => Outcome::Jog(plan, mdeg),
            Err(Refusal::LatheTurning) => {
                Outcome::LatheTurning(status::LatheSeen::of(ctl), "jog only with the lathe at rest")
            }
            Err(r) => Outcome::Error(r.describe()),
        },
        Command::SelfTest(op) => selftest::apply(op, pre.and_then(|p| p.selftest.map(|s| (p.generation, s))), ctl),
        Command::Divide(op) => divide::apply(op, ctl),
        Command::Dfu => match ctl.admit(crate::controller::Asked::Dfu) {
            Ok(()) => Outcome::Dfu,
            Err(r) => Outcome::Error(r.describe()),
        },
    }
}

/// The reply line, and what the firmware must do besides sending it.
pub fn render(outcome: &Outcome) -> (Reply, Action) {
    let mut out = Reply::new();
    write_reply(outcome, &mut out);
    (out, action(outcome))
}

/// What the firmware must do besides sending the reply.
fn action(outcome: &Outcome) -> Action {
    match outcome {
        Outcome::Watch(_) => Action::Watch,
        Outcome::Save => Action::Save,
        Outcome::Dfu => Action::Dfu,
        Outcome::Text(_)
        | Outcome::Error(_)
        | Outcome::FieldError(..)
        | Outcome::Misfit(_)
        | Outcome::Value(..)
        | Outcome::All(_)
        | Outcome::State(_)
        | Outcome::Status(_)
        | Outcome::Encoder(..)
        | Outcome::Jog(..)
        | Outcome::SelfTestStarted(..)
        | Outcome::SelfTestRefused(_)
        | Outcome::SelfTest(_)
        | Outcome::Divide(_)
        | Outcome::LatheTurning(..) => Action::None,
    }
}

/// The reply line itself.
fn write_reply(outcome: &Outcome, out: &mut Reply) {
    match outcome {
        Outcome::Text(t) => {
            let _ = out.push_str(t);
        }
        Outcome::Error(msg) => {
            let _ = write!(out, "error: {msg}");
        }
        Outcome::FieldError(field, allowed) => {
            let _ = write!(out, "error: {field} {allowed}");
        }
        Outcome::Misfit(m) => misfit::write(m, out),
        Outcome::Value(c, name) => {
            let _ = out.push_str("ok ");
            value_of(c, name, out);
        }
        Outcome::All(c) => get_all(c, out),
        Outcome::State(name) => {
            let _ = write!(out, "ok {name}");
        }
        Outcome::Status(s) | Outcome::Watch(s) => s.write(out),
        Outcome::Save => {
            let _ = out.push_str("ok saving");
        }
        Outcome::Encoder(r, op) => checks::write_encoder(r, *op, out),
        Outcome::Jog(plan, mdeg) => checks::write_jog(plan, *mdeg, out),
        Outcome::SelfTestStarted(rpm, cpr, ms) => selftest::write_started(*rpm, *cpr, *ms, out),
        Outcome::SelfTestRefused(r) => selftest::write_refused(*r, out),
        Outcome::SelfTest(r) => selftest::write_report(r, out),
        Outcome::Divide(s) => status::angle::write_readout(s, out),
        Outcome::Dfu => {
            let _ = out.push_str(checks::DFU_REPLY);
        }
        Outcome::LatheTurning(seen, then) => {
            let _ = write!(out, "error: stop the lathe first: {seen}: {then}");
        }
    }
}

/// Handles one line (without its line ending): parse, apply, render.
pub fn handle(line: &[u8], ctl: &mut Controller) -> (Reply, Action) {
    render(&apply(parse(line), ctl))
}

fn get_all(c: &Config, out: &mut Reply) {
    let _ = out.push_str("ok");
    for name in NAMES {
        let _ = out.push(' ');
        value_of(c, name, out);
    }
}

/// Appends `name=value`; false for an unknown name.
fn value_of(c: &Config, name: &str, out: &mut Reply) -> bool {
    named(c, name, '=', out)
}

/// Appends the name, `sep` and the value (`name=value` in `get`, `name
/// value` in a sentence); false for an unknown name.
fn named(c: &Config, name: &str, sep: char, out: &mut Reply) -> bool {
    let Some(name) = NAMES.iter().find(|n| **n == name) else { return false };
    let _ = write!(out, "{name}{sep}");
    let _ = match *name {
        "cpr" => write!(out, "{}", c.encoder_counts_per_rev),
        "steps" => write!(out, "{}", c.motor_steps_per_rev),
        "ratio" => write!(out, "{}", c.ratio),
        "dir" => write!(out, "{}", if c.sense == Sense::Same { "same" } else { "opposite" }),
        "edges" => write!(out, "{}", c.edges),
        "max-rate" => write!(out, "{}", c.max_step_rate_hz),
        "max-accel" => write!(out, "{}", c.max_accel_steps_per_s2),
        "ferror" => write!(out, "{}", c.following_error_limit_steps),
        "phase" => write_mdeg(out, c.phase_offset_mdeg),
        "drive" => write!(
            out,
            "{}",
            match c.drive {
                DriveKind::Stepper => "stepper",
                DriveKind::Bldc => "bldc",
                DriveKind::None => "none",
            }
        ),
        "dir-setup" => write!(out, "{}", c.dir_setup_ns),
        "pulse" => write!(out, "{}", c.step_pulse_ns),
        "enable" => write!(out, "{}", if c.enable_active_high { "high" } else { "low" }),
        "max-rpm" => write!(out, "{}", c.max_lathe_rpm),
        "cutter-cpr" if c.cutter_encoder_cpr == 0 => write!(out, "off"),
        "cutter-cpr" => write!(out, "{}", c.cutter_encoder_cpr),
        "lost-steps" => write!(out, "{}", c.lost_step_limit_steps),
        "start-rate" => write!(out, "{}", c.start_rate_hz),
        "bldc-out" => write!(out, "{}", c.bldc_out.name()),
        "pwm-hz" => write!(out, "{}", c.pwm_hz),
        "bldc-tau" => write!(out, "{}", c.bldc_tau_ms),
        _ => Ok(()),
    };
    true
}

fn write_mdeg(out: &mut Reply, mdeg: i32) -> core::fmt::Result {
    let sign = if mdeg < 0 { "-" } else { "" };
    let m = mdeg.unsigned_abs();
    write!(out, "{sign}{}.{:03}", m / 1000, m % 1000)
}

pub mod tag;

#[cfg(test)]
mod command_tests;
#[cfg(test)]
mod tests;
