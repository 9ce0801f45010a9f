//! `jog`: turn the cutter by a set angle, slowly, with the lathe at rest,
//! so the machinist sees which way it turns and checks that one commanded
//! turn is one real turn (a microstep setting the drive does not have
//! shows here, before any metal is cut). The move is the follower's: the
//! same step output and limits as a cut, at a walking pace.

use super::activity::{Activity, Asked, Jog};
use super::{Controller, Refusal};
use crate::config::DriveKind;
use crate::follower::{Follower, Limits};
use crate::state::State;

/// One cutter turn in this many seconds at most: slow enough to watch.
pub const JOG_SECONDS_PER_TURN: u32 = 2;
/// The largest jog, in millidegrees of the cutter (ten turns).
pub const JOG_MAX_MDEG: i32 = 3_600_000;

/// Counts the lathe may move during a jog (a knock on the chuck) before
/// the jog stops: a jog is only for a lathe at rest.
pub const JOG_LATHE_SLACK: i64 = 4;

/// What a jog will do, for the reply.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JogPlan {
    /// signed motor steps (or cutter-encoder counts, BLDC)
    pub steps: i64,
    /// the jog's top speed, steps per second
    pub rate_hz: u32,
}

impl Controller {
    /// Starts a jog of `mdeg` millidegrees of the cutter, in the direction
    /// the gear turns it when the lathe counts up (so `dir` decides it,
    /// as it will when cutting). Low priority: divides.
    pub fn jog(&mut self, mdeg: i32) -> Result<JogPlan, Refusal> {
        self.admit(Asked::Jog)?;
        if self.config.drive == DriveKind::None {
            return Err(Refusal::NoCutter);
        }
        if !self.lathe_at_rest() {
            return Err(Refusal::LatheTurning);
        }
        let m = self.config.motor_steps_per_rev as i64;
        let signed = if self.d.sense_positive { mdeg as i64 } else { -(mdeg as i64) };
        // round half away from zero: a 1/2-step angle still moves
        let steps = (signed * m + signed.signum() * 180_000) / 360_000;
        if steps == 0 || mdeg.unsigned_abs() > JOG_MAX_MDEG as u32 {
            return Err(Refusal::JogRange);
        }
        let slow = (self.config.motor_steps_per_rev / JOG_SECONDS_PER_TURN).max(1);
        let rate_hz = slow.min(self.config.max_step_rate_hz);
        let tick_hz = self.timing.tick_hz as u64;
        let limits = Limits::from_rates(rate_hz as u64, self.config.max_accel_steps_per_s2 as u64, tick_hz);
        // From whole steps: idle re-seats the follower on the measured
        // cutter each tick, but the tick that ended a ramp leaves it where
        // the ramp did (a fractional target never matches the steps
        // counted, and the jog would never end).
        let start = crate::q16::from_steps(self.follower.whole_steps());
        self.follower = Follower { position: start, velocity: 0 };
        let ticks = steps.unsigned_abs() * tick_hz / rate_hz as u64;
        let deadline = self.ticks + 2 * ticks + tick_hz;
        let target = start + crate::q16::from_steps(steps);
        let dividing = self.divide();
        self.activity = Activity::Jog(Jog { target, limits, deadline, lathe: self.lathe.position(), dividing });
        self.state = State::Jogging;
        Ok(JogPlan { steps, rate_hz })
    }

    /// One tick of a jog: toward the target within the jog's limits; done
    /// once the commanded position is there and (stepper) every step of it
    /// has been emitted.
    pub(super) fn step_jog(&mut self, cutter: i64) {
        let Activity::Jog(j) = self.activity else {
            self.state = State::Idle;
            return;
        };
        // the lathe started, or the jog overran its time: stop (ramped)
        let knocked = (self.lathe.position() - j.lathe).abs() > JOG_LATHE_SLACK;
        if knocked || self.ticks > j.deadline {
            self.end_jog();
            self.state = State::Disengaging;
            return self.follower.ramp_down(&self.d.limits);
        }
        self.follower.track(j.target, 0, &j.limits);
        let close = (j.target - self.follower.position).abs() < crate::q16::HALF;
        if close && self.follower.velocity.abs() <= j.limits.max_accel {
            // within half a step and all but stopped: there
            self.follower = Follower { position: j.target, velocity: 0 };
            let emitted = self.config.drive != DriveKind::Stepper || cutter == j.target;
            if emitted {
                self.end_jog();
                self.state = State::Idle;
            }
        }
    }
}
