//! The console busy through a cut at the top step rate: what a machinist at
//! the keyboard does while the cutter runs (`status` ten times a second, a
//! phase nudge twice a second, a `get` now and then), each answered while
//! the tick and its plan keep every step on its cycle. The job's settings
//! (`top_rate`) put the cutter at 228 000 steps/s with `max-rate` 250 000:
//! engaging takes a lathe whose cutter would run within 15/16 of max-rate
//! (`Controller::engage`), 234 375 steps/s, and the lathe's 2 % ripple
//! stays within it.

use crate::machine::Machine;
use crate::usb::scenario;

/// Motor steps a cutter turn and the top step rate: 600 rpm × 2 × 11 400 / 60
/// = 228 000 steps/s.
pub const STEPS: u32 = 11_400;
pub const MAX_RATE_HZ: u32 = 250_000;
/// The lathe's top speed the settings allow: 650 × 2 × 11 400 / 60 = 247 000
/// steps/s, within `MAX_RATE_HZ`, so the board takes the settings.
pub const MAX_LATHE_RPM: u32 = 650;
/// The cutter's acceleration limit, steps/s².
pub const MAX_ACCEL: u32 = 2_000_000;

/// What the console answered.
#[derive(Default)]
pub struct Answers {
    pub sent: u32,
    pub ok: u32,
    /// the first reply that was not `ok`, or no reply
    pub first_bad: Option<String>,
    /// `status` replies that said the cutter was synchronised, and the last
    pub synced: u32,
    pub last_status: String,
}

/// The settings of a top-rate job on a scenario's.
pub fn top_rate(c: &mut polyturn_sync::Config) {
    // a stepper at these rates is set up with a quick ramp: 400 000
    // steps/s² (the default) leaves it a second behind the lathe, catching
    // up by the 9 % of max-rate the target leaves it for three more
    c.max_accel_steps_per_s2 = MAX_ACCEL;
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
    if let Ok((r, _, _)) = scenario::exchange(m, "status\n") {
        a.synced += r.contains("state=synced") as u32;
        a.last_status = r;
    }
    if k.is_multiple_of(5) {
        let nudge = if (k / 5).is_multiple_of(2) { "set phase 0.5\n" } else { "set phase 0\n" };
        ask(m, nudge);
    }
    if k.is_multiple_of(10) {
        ask(m, "get ratio\n");
    }
}
