//! The console busy through a cut at the top step rate: what a machinist at
//! the keyboard does while the cutter runs (`status` ten times a second, a
//! phase nudge twice a second, a `get` now and then), each answered while
//! the tick and its plan keep every step on its cycle. The job's settings
//! (`top_rate`) put the cutter at 240 000 steps/s, under `max-rate` 250 000.

use crate::machine::Machine;
use crate::usb::scenario;

/// Motor steps a cutter turn and the top step rate: 600 rpm × 2 × 12 000 / 60
/// = 240 000 steps/s.
pub const STEPS: u32 = 12_000;
pub const MAX_RATE_HZ: u32 = 250_000;
/// The lathe's top speed the settings allow: 625 × 2 × 12 000 / 60 is
/// `MAX_RATE_HZ`, so the board takes the settings.
pub const MAX_LATHE_RPM: u32 = 625;

/// What the console answered.
#[derive(Default)]
pub struct Answers {
    pub sent: u32,
    pub ok: u32,
    /// the first reply that was not `ok`, or no reply
    pub first_bad: Option<String>,
}

/// The settings of a top-rate job on a scenario's.
pub fn top_rate(c: &mut polyturn_sync::Config) {
    c.motor_steps_per_rev = STEPS;
    c.max_step_rate_hz = MAX_RATE_HZ;
    c.max_lathe_rpm = MAX_LATHE_RPM;
    c.following_error_limit_steps = STEPS / 50;
}

/// One 100 ms slice of a busy cut: `status`, and on every fifth slice a
/// phase nudge (alternately ±0.5°, so the cut ends where it began), on every
/// tenth a `get ratio`.
pub fn slice(m: &mut Machine, k: u32, a: &mut Answers) {
    let mut ask = |m: &mut Machine, line: &str| {
        a.sent += 1;
        match scenario::exchange(m, line) {
            Ok((r, _, _)) if r.starts_with("ok") => a.ok += 1,
            Ok((r, _, _)) => drop(a.first_bad.get_or_insert(format!("{line:?}: {r}"))),
            Err(e) => drop(a.first_bad.get_or_insert(format!("{line:?}: {e}"))),
        }
    };
    ask(m, "status\n");
    if k % 5 == 0 {
        let nudge = if (k / 5) % 2 == 0 { "set phase 0.5\n" } else { "set phase 0\n" };
        ask(m, nudge);
    }
    if k % 10 == 0 {
        ask(m, "get ratio\n");
    }
}
