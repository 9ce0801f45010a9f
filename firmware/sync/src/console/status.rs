//! The `status` line: state, fault, speeds and phase error, in units a
//! machinist reads (rpm, steps), computed at low priority.

pub(super) mod angle;

use super::Reply;
use crate::config::Config;
use crate::controller::{Controller, ShaftGap, Status};
use crate::state::Fault;
use core::fmt::Write;

/// What a status line needs, copied out of the controller (cheap), so the
/// formatting (slow: i128 arithmetic, core::fmt) runs outside its lock.
#[derive(Clone, Copy, Debug)]
pub struct Snapshot {
    pub status: Status,
    pub config: Config,
    pub tick_hz: u32,
    pub fault: Option<Fault>,
    /// the points of the cam table fitted to the X axis, if one is (at most
    /// CAM_POINTS, 1024; a u16 keeps `Outcome` small)
    pub cam_points: Option<u16>,
    /// with a cutter encoder: the shaft's distance from the steps sent
    /// (`lost-steps`), divided into steps when the line is written
    pub shaft_gap: Option<ShaftGap>,
}

impl Snapshot {
    pub fn of(ctl: &Controller) -> Snapshot {
        Snapshot {
            status: ctl.status(),
            config: *ctl.config(),
            tick_hz: ctl.derived().tick_hz,
            fault: ctl.fault(),
            cam_points: ctl.x_axis().map(|x| x.cam.points().len() as u16),
            shaft_gap: ctl.shaft_gap(),
        }
    }

    /// Writes `ok state=... fault=... lathe_rpm=... cutter_rpm=... phase_err_steps=...`,
    /// then `cam=N` (its points) while a cam table is fitted: whether an
    /// upload, or the one saved, took is seen without the upload's reply;
    /// with a cutter encoder, `shaft_err_steps` (steps sent − shaft).
    pub fn write(&self, out: &mut Reply) {
        let (s, c) = (&self.status, &self.config);
        let lathe_rpm10 = lathe_rpm10(s.lathe_velocity_q32, self.tick_hz, c.encoder_counts_per_rev);
        // the speed the cutter is driven at, not the lathe's × ratio: 0 while
        // idle, the jog's while jogging, in the motor's own sense (its steps
        // count down with dir=opposite while the lathe's encoder counts up).
        // |v| ≤ max-rate / tick rate < 2^20 (Q16), × hz · 600 < 2^45.
        let cutter_rpm10 = s.cutter_velocity_q16 * self.tick_hz as i64 * 600 / ((c.motor_steps_per_rev as i64) << 16);
        let err = Milli::steps_q16(s.phase_error_q16);
        let fault = self.fault.map(|f| f.name()).unwrap_or("none");
        let _ = write!(
            out,
            "ok state={} fault={} lathe_rpm={} cutter_rpm={} phase_err_steps={} target={} cutter={} indexed={}",
            s.state.name(),
            fault,
            Tenths(lathe_rpm10),
            Tenths(cutter_rpm10),
            err,
            s.target_steps,
            s.cutter_steps,
            if s.indexed { "yes" } else { "no" },
        );
        angle::write_angle(self, out);
        angle::write_division(self, out);
        if let Some(n) = self.cam_points {
            let _ = write!(out, " cam={n}");
        }
        if let Some(g) = self.shaft_gap {
            let _ = write!(out, " shaft_err_steps={}", Milli(g.milli_steps()));
        }
        if let Some(f) = self.fault {
            let _ = write!(out, " reason=\"{}\"", f.reason());
        }
    }
}

/// What the board saw of a lathe it does not take to be at rest: the time
/// since its encoder's last count, and the time without a count that is at
/// rest (`Controller::lathe_at_rest`). (Not its speed: a change of the
/// settings measures that afresh, while the count's time stands.)
#[derive(Clone, Copy, Debug)]
pub struct LatheSeen {
    since_count_ticks: u32,
    still_ticks: u32,
    tick_hz: u32,
}

impl LatheSeen {
    pub fn of(ctl: &Controller) -> LatheSeen {
        LatheSeen {
            since_count_ticks: ctl.ticks_since_lathe_count(),
            still_ticks: ctl.derived().still_ticks,
            tick_hz: ctl.derived().tick_hz,
        }
    }
}

/// `its encoder counted N ms ago (at rest after M ms without a count)`
impl core::fmt::Display for LatheSeen {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let ms = |ticks: u32| ticks as u64 * 1000 / self.tick_hz.max(1) as u64;
        let (ago, rest) = (ms(self.since_count_ticks), ms(self.still_ticks));
        write!(f, "its encoder counted {ago} ms ago (at rest after {rest} ms without a count)")
    }
}

/// Why a complete cam table is not saved now: the board saves it (and
/// pauses the controller) only idle, with the lathe at rest.
#[derive(Clone, Copy, Debug)]
pub enum CamWait {
    Running,
    LatheTurning(LatheSeen),
}

/// Whether a complete cam table may be saved now (`None`), or why not.
pub fn cam_wait(ctl: &mut Controller) -> Option<CamWait> {
    if ctl.state() != crate::state::State::Idle {
        Some(CamWait::Running)
    } else if !ctl.lathe_at_rest() {
        Some(CamWait::LatheTurning(LatheSeen::of(ctl)))
    } else {
        None
    }
}

impl core::fmt::Display for CamWait {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CamWait::Running => f.write_str("stop first: the cam changes only while idle"),
            CamWait::LatheTurning(seen) => write!(f, "stop the lathe first: {seen}: the table is saved to flash"),
        }
    }
}

/// The lathe's speed, tenths of an rpm: v[Q16 counts/tick] · hz · 600 /
/// (2^16 · E), all within i64: |v| < 2^30 (Q16, ≤ 16 000 counts/tick) and
/// hz · 600 < 2^25.
fn lathe_rpm10(velocity_q32: i64, tick_hz: u32, counts_per_rev: u32) -> i64 {
    (velocity_q32 >> 16) * tick_hz as i64 * 600 / ((counts_per_rev.max(1) as i64) << 16)
}

/// The status line of a controller (host and tests; the firmware snapshots
/// under its lock and writes outside it).
pub fn write_status(ctl: &Controller, out: &mut Reply) {
    Snapshot::of(ctl).write(out);
}

pub(crate) struct Tenths(pub(crate) i64);
impl core::fmt::Display for Tenths {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let sign = if self.0 < 0 { "-" } else { "" };
        write!(f, "{sign}{}.{}", self.0.unsigned_abs() / 10, self.0.unsigned_abs() % 10)
    }
}

pub(crate) struct Milli(pub(crate) i64);

impl Milli {
    /// Q16 steps as thousandths of a step (clamped to ±2^46 so the
    /// product fits).
    pub(crate) fn steps_q16(q16: i64) -> Milli {
        Milli((q16.clamp(-(1 << 46), 1 << 46) * 1000) >> 16)
    }
}
impl core::fmt::Display for Milli {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let sign = if self.0 < 0 { "-" } else { "" };
        write!(f, "{sign}{}.{:03}", self.0.unsigned_abs() / 1000, self.0.unsigned_abs() % 1000)
    }
}

#[cfg(test)]
mod tests;
