//! The BLDC cutter drive behind the follower: a speed loop on the cutter's
//! encoder. (The step/dir books are in `steps`: `steps::book` for the X
//! axis, `steps::pipe` for the cutter's hardware-timed output.)

use crate::derived::Derived;
use crate::encoder::Extender;
use crate::follower::Follower;

pub mod gains;
pub use gains::BldcGains;

/// BLDC: speed command = feed-forward (the follower's speed, and its
/// acceleration times the drive's lag) + PI on the phase error seen by the
/// cutter's encoder, with gains from the drive (`gains`), clamped, with
/// anti-windup.
#[derive(Clone, Copy, Debug, Default)]
pub struct Bldc {
    encoder: Extender,
    /// the integral term, Q16 counts per tick × 2^32
    integral: i64,
    still: u32,
    last: i64,
    last_velocity: i64,
    last_error: i64,
    /// the error's rate, filtered: Q16 counts per tick
    rate: i64,
}

/// The phase error taken into the products: 65 536 counts (past it every
/// gain saturates the command anyway), so `gains`' products fit 64 bits.
pub const ERROR_BOUND: i64 = 1 << 32;

impl Bldc {
    pub fn start(&mut self, raw: u16) {
        self.encoder = Extender::new(raw);
    }

    #[inline]
    pub fn read(&mut self, raw: u16) -> i64 {
        self.encoder.update(raw);
        self.encoder.position()
    }

    /// Disabled: the next run starts afresh. It starts from the cutter's
    /// own place at rest (the follower's error and speed 0), so no rate or
    /// acceleration is taken against the run before.
    pub fn reset(&mut self) {
        self.integral = 0;
        self.still = 0;
        self.rate = 0;
        self.last_error = 0;
        self.last_velocity = 0;
    }

    /// Returns the speed command (Q16 counts per tick) and whether the
    /// motor has stalled (commanded to move, encoder still for too long).
    #[inline]
    pub fn command(&mut self, f: &Follower, cutter_q16: i64, d: &Derived) -> (i32, bool) {
        let error = crate::q16::bound(f.position - cutter_q16, ERROR_BOUND);
        // the follower's change of speed this tick, within its own limit
        // (a start-rate jump would otherwise be one tick's spike)
        let accel = crate::q16::bound(f.velocity - self.last_velocity, d.limits.max_accel);
        self.last_velocity = f.velocity;
        let g = &d.bldc;
        // the speed error: the error's change, filtered (a count's step
        // spread over 2^shift ticks)
        self.rate += (error - self.last_error - self.rate) >> g.rate_shift;
        self.last_error = error;
        // At standstill on the commanded count: hold, do not hunt ±1 count
        // (the encoder cannot see finer; integrating would limit-cycle).
        if f.velocity == 0 && f.whole_steps() == cutter_q16 >> 16 {
            self.still = 0;
            return (0, false);
        }
        // Multiplies and shifts: no division in the tick.
        let umax = d.limits.max_velocity + (d.limits.max_velocity >> 1);
        // Every interface drives the cutter only its wired way
        // (`polyturn_firmware::bldcout`): the other way is a saturation at
        // 0, for the anti-windup and the stall check alike.
        let (lo, hi) = if d.sense_positive { (0, umax) } else { (-umax, 0) };
        let step = error * g.ki_q32;
        let integral = crate::q16::bound(self.integral + step, umax << 32);
        let feedback = ((error * g.kp_q16) >> 16) + ((self.rate * g.kv_q8) >> 8) + (integral >> 32);
        let raw = f.velocity + accel * g.tau_ticks + feedback;
        // (max then min: `clamp` carries a panic for lo > hi)
        let u = raw.max(lo).min(hi);
        // Anti-windup: integrate only while the output is not saturated
        // in the direction the error pushes.
        if u == raw || (raw > u) != (step > 0) {
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
