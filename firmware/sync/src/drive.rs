//! The BLDC cutter drive behind the follower: a speed loop on the cutter's
//! encoder. (The step/dir books are in `steps`: `steps::book` for the X
//! axis, `steps::pipe` for the cutter's hardware-timed output.)

use crate::derived::Derived;
use crate::encoder::Extender;
use crate::follower::Follower;

/// BLDC: speed command = feed-forward (the follower's speed) + PI on the
/// phase error seen by the cutter's encoder, clamped, with anti-windup.
#[derive(Clone, Copy, Debug, Default)]
pub struct Bldc {
    encoder: Extender,
    integral: i64,
    still: u32,
    last: i64,
}

/// Proportional: 1/16 of the phase error per tick; integral: 1/1024.
const KP_SHIFT: u32 = 4;
const KI_SHIFT: u32 = 10;

impl Bldc {
    pub fn start(&mut self, raw: u16) {
        self.encoder = Extender::new(raw);
    }

    #[inline]
    pub fn read(&mut self, raw: u16) -> i64 {
        self.encoder.update(raw);
        self.encoder.position()
    }

    pub fn reset(&mut self) {
        self.integral = 0;
        self.still = 0;
    }

    /// Returns the speed command (Q16 counts per tick) and whether the
    /// motor has stalled (commanded to move, encoder still for too long).
    #[inline]
    pub fn command(&mut self, f: &Follower, cutter_q16: i64, d: &Derived) -> (i32, bool) {
        let error = f.position - cutter_q16;
        // At standstill on the commanded count: hold, do not hunt ±1 count
        // (the encoder cannot see finer; integrating would limit-cycle).
        if f.velocity == 0 && f.whole_steps() == cutter_q16 >> 16 {
            self.still = 0;
            return (0, false);
        }
        // Shifts, not `/`: a size-optimised build would call __aeabi_ldivmod.
        let umax = d.limits.max_velocity + (d.limits.max_velocity >> 1);
        let step = error >> KI_SHIFT;
        let integral = crate::q16::bound(self.integral + step, umax);
        let raw = f.velocity + (error >> KP_SHIFT) + integral;
        let u = crate::q16::bound(raw, umax);
        // Anti-windup: integrate only while the output is not saturated
        // in the direction the error pushes.
        if u == raw || (raw > umax) != (step > 0) {
            self.integral = integral;
        }
        let moved = cutter_q16 != self.last;
        self.last = cutter_q16;
        self.still = if moved || u.abs() < d.limits.max_velocity >> 4 { 0 } else { self.still + 1 };
        (u as i32, self.still > d.stall_ticks)
    }
}

#[cfg(test)]
mod bldc_tests;
