//! The console protocol: one line in, one line out (`ok ...` or
//! `error: ...`), no allocation. Used by the firmware's USB console, by
//! `polyturn device` and by tests. Any bytes get an answer; an error never
//! changes a setting.

use crate::config::{Config, DriveKind, Sense, NAMES};
use crate::controller::Controller;
use core::fmt::Write;

/// Longest reply line.
pub const REPLY_LEN: usize = 320;
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
}

pub use crate::console_status::write_status as status_line;

pub const HELP: &str = "ok commands: get [name] | set <name> <value> | engage | stop | status | watch | save | defaults | clear | help; names: cpr steps ratio dir edges max-rate max-accel ferror phase drive dir-setup pulse enable max-rpm";

/// Handles one line (without its line ending).
pub fn handle(line: &[u8], ctl: &mut Controller) -> (Reply, Action) {
    let mut out = Reply::new();
    let action = match core::str::from_utf8(line) {
        Ok(text) => dispatch(text.trim(), ctl, &mut out),
        Err(_) => fail(&mut out, "not text: commands are plain ASCII (try help)"),
    };
    (out, action)
}

fn fail(out: &mut Reply, msg: &str) -> Action {
    out.clear();
    let _ = write!(out, "error: {msg}");
    Action::None
}

fn dispatch(text: &str, ctl: &mut Controller, out: &mut Reply) -> Action {
    let mut words = text.split_ascii_whitespace();
    let cmd = words.next().unwrap_or("");
    let (a, b, extra) = (words.next(), words.next(), words.next());
    match (cmd, a, b, extra) {
        ("help", None, ..) | ("?", None, ..) => {
            let _ = out.push_str(HELP);
        }
        ("get", None, ..) => get_all(ctl.config(), out),
        ("get", Some(name), None, _) => match out.push_str("ok ").is_ok() && value_of(ctl.config(), name, out) {
            true => {}
            false => return fail(out, "get: unknown name (try help)"),
        },
        ("set", Some(name), Some(value), None) => return set(ctl, name, value, out),
        ("set", ..) => return fail(out, "usage: set <name> <value>"),
        ("engage", None, ..) => match ctl.engage() {
            Ok(()) => {
                let _ = out.push_str("ok engaging");
            }
            Err(r) => return fail(out, r.describe()),
        },
        ("stop", None, ..) => {
            ctl.disengage();
            let _ = out.push_str("ok stopping");
        }
        ("clear", None, ..) => {
            ctl.clear();
            let _ = write!(out, "ok {}", ctl.state().name());
        }
        ("status", None, ..) => crate::console_status::write_status(ctl, out),
        ("watch", None, ..) => {
            crate::console_status::write_status(ctl, out);
            return Action::Watch;
        }
        ("save", None, ..) => {
            if ctl.state() != crate::state::State::Idle {
                return fail(out, "stop first: settings are saved only while idle");
            }
            if !ctl.lathe_at_rest() {
                return fail(out, "stop the lathe first: saving pauses the controller for up to 2 s");
            }
            let _ = out.push_str("ok saving");
            return Action::Save;
        }
        ("defaults", None, ..) => match ctl.set_config(Config::default()) {
            Ok(()) => {
                let _ = out.push_str("ok defaults loaded (not saved: use save)");
            }
            Err(r) => return fail(out, r.describe()),
        },
        ("", ..) => return fail(out, "empty line (try help)"),
        _ => return fail(out, "unknown command or wrong arguments (try help)"),
    }
    Action::None
}

fn set(ctl: &mut Controller, name: &str, value: &str, out: &mut Reply) -> Action {
    match ctl.config().with(name, value) {
        Err(e) => {
            out.clear();
            let _ = write!(out, "error: {} {}", e.field, e.allowed);
        }
        Ok(c) => match ctl.set_config(c) {
            Ok(()) => {
                let _ = out.push_str("ok ");
                value_of(ctl.config(), name, out);
            }
            Err(r) => return fail(out, r.describe()),
        },
    }
    Action::None
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
    let _ = match name {
        "cpr" => write!(out, "cpr={}", c.encoder_counts_per_rev),
        "steps" => write!(out, "steps={}", c.motor_steps_per_rev),
        "ratio" => write!(out, "ratio={}", c.ratio),
        "dir" => write!(out, "dir={}", if c.sense == Sense::Same { "same" } else { "opposite" }),
        "edges" => write!(out, "edges={}", c.edges),
        "max-rate" => write!(out, "max-rate={}", c.max_step_rate_hz),
        "max-accel" => write!(out, "max-accel={}", c.max_accel_steps_per_s2),
        "ferror" => write!(out, "ferror={}", c.following_error_limit_steps),
        "phase" => write_mdeg(out, c.phase_offset_mdeg),
        "drive" => write!(out, "drive={}", if c.drive == DriveKind::Stepper { "stepper" } else { "bldc" }),
        "dir-setup" => write!(out, "dir-setup={}", c.dir_setup_ns),
        "pulse" => write!(out, "pulse={}", c.step_pulse_ns),
        "enable" => write!(out, "enable={}", if c.enable_active_high { "high" } else { "low" }),
        "max-rpm" => write!(out, "max-rpm={}", c.max_lathe_rpm),
        _ => return false,
    };
    true
}

fn write_mdeg(out: &mut Reply, mdeg: i32) -> core::fmt::Result {
    let sign = if mdeg < 0 { "-" } else { "" };
    let m = mdeg.unsigned_abs();
    write!(out, "phase={sign}{}.{:03}", m / 1000, m % 1000)
}

#[cfg(test)]
mod tests;
