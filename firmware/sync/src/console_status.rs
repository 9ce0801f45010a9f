//! The `status` line: state, fault, speeds and phase error, in units a
//! machinist reads (rpm, steps), computed at low priority.

use crate::console::Reply;
use crate::controller::Controller;
use core::fmt::Write;

/// Writes `ok state=... fault=... lathe_rpm=... cutter_rpm=... phase_err_steps=...`.
pub fn write_status(ctl: &Controller, out: &mut Reply) {
    let s = ctl.status();
    let c = ctl.config();
    let hz = ctl.derived().tick_hz as i128;
    // rpm ×10 = v[Q32 counts/tick] · hz · 60 · 10 / (2^32 · E)
    let lathe_rpm10 =
        (s.lathe_velocity_q32 as i128 * hz * 600 / (c.encoder_counts_per_rev as i128 * (1i128 << 32))) as i64;
    let cutter_rpm10 = lathe_rpm10 * c.ratio.num() as i64 / c.ratio.den() as i64;
    let err_milli = ((s.phase_error_q16 as i128 * 1000) >> 16) as i64;
    let fault = ctl.fault().map(|f| f.name()).unwrap_or("none");
    let _ = write!(
        out,
        "ok state={} fault={} lathe_rpm={} cutter_rpm={} phase_err_steps={} target={} cutter={} indexed={}",
        s.state.name(),
        fault,
        Tenths(lathe_rpm10),
        Tenths(cutter_rpm10),
        Milli(err_milli),
        s.target_steps,
        s.cutter_steps,
        if s.indexed { "yes" } else { "no" },
    );
    if let Some(f) = ctl.fault() {
        let _ = write!(out, " reason=\"{}\"", f.reason());
    }
}

struct Tenths(i64);
impl core::fmt::Display for Tenths {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let sign = if self.0 < 0 { "-" } else { "" };
        write!(f, "{sign}{}.{}", self.0.unsigned_abs() / 10, self.0.unsigned_abs() % 10)
    }
}

struct Milli(i64);
impl core::fmt::Display for Milli {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let sign = if self.0 < 0 { "-" } else { "" };
        write!(f, "{sign}{}.{:03}", self.0.unsigned_abs() / 1000, self.0.unsigned_abs() % 1000)
    }
}
