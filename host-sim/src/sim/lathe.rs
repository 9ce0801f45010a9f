//! The lathe spindle: a speed profile integrated to an angle, with ripple
//! (once-per-rev sinusoid plus seeded random wander), optional load dips and
//! a reversal, and always a deceleration to rest at the end.

use super::rng::Rng;
use std::f64::consts::TAU;

/// One leg of the profile: reach `rpm` (signed) at `accel_rpm_per_s`,
/// then hold it for `hold_s` seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leg {
    pub rpm: f64,
    pub accel_rpm_per_s: f64,
    pub hold_s: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct LatheProfile {
    pub start_rpm: f64,
    pub legs: Vec<Leg>,
    /// fraction of speed: once-per-rev sinusoid amplitude
    pub ripple: f64,
    /// fraction of speed: random wander amplitude (≈ ripple / 5)
    pub wander: f64,
    /// (time s, duration s, fraction): speed dips under cutting load
    pub dips: Vec<(f64, f64, f64)>,
}

pub struct Lathe {
    profile: LatheProfile,
    /// commanded base speed, rev/s
    base: f64,
    leg: usize,
    held: f64,
    pub angle: f64,
    pub speed: f64,
    pub time: f64,
    wander: f64,
    rng: Rng,
    /// sin and cos of the angle, advanced by rotation (no sin() per step)
    phasor: (f64, f64),
    steps: u32,
    /// each leg's speed (rev/s) and acceleration (rev/s²), worked out once
    /// (the simulator's loop ran these divisions every tick)
    rates: Vec<(f64, f64)>,
    /// the step at which the wander is next drawn, once a millisecond
    next_draw: Option<u32>,
}

impl Lathe {
    pub fn new(profile: LatheProfile, seed: u64) -> Lathe {
        let base = profile.start_rpm / 60.0;
        let rates = profile.legs.iter().map(|l| (l.rpm / 60.0, l.accel_rpm_per_s / 60.0)).collect();
        Lathe {
            profile,
            rates,
            next_draw: None,
            base,
            leg: 0,
            held: 0.0,
            angle: 0.0,
            speed: base * TAU,
            time: 0.0,
            wander: 0.0,
            rng: Rng::new(seed),
            phasor: (0.0, 1.0),
            steps: 0,
        }
    }

    /// True once every leg has been run and the spindle is at rest.
    pub fn finished(&self) -> bool {
        self.leg >= self.profile.legs.len()
    }

    /// True while the profile holds a steady set speed (not ramping).
    pub fn holding(&self) -> bool {
        self.rates.get(self.leg).is_some_and(|&(goal, _)| (goal - self.base).abs() < 1e-12 && goal != 0.0)
    }

    /// Ends the current hold now (the machinist stops the lathe).
    pub fn end_hold(&mut self) {
        if self.holding() {
            self.leg += 1;
            self.held = 0.0;
        }
    }

    /// Advances `dt` seconds.
    pub fn advance(&mut self, dt: f64) {
        self.time += dt;
        if let Some(leg) = self.profile.legs.get(self.leg).copied() {
            let (goal, accel) = self.rates[self.leg];
            let dv = accel * dt;
            if (goal - self.base).abs() <= dv {
                self.base = goal;
                self.held += dt;
                if self.held >= leg.hold_s {
                    self.leg += 1;
                    self.held = 0.0;
                }
            } else {
                self.base += dv * (goal - self.base).signum();
            }
        }
        // Wander: a slow first-order random walk (≈ 20 ms correlation),
        // drawn once a millisecond.
        self.steps = self.steps.wrapping_add(1);
        let every = |dt: f64| ((1e-3 / dt) as u32).max(1);
        let next = *self.next_draw.get_or_insert_with(|| every(dt));
        if self.steps == next {
            let every = every(dt);
            self.next_draw = Some(next.wrapping_add(every));
            self.wander += (self.rng.normal() * 0.3 - self.wander) * (every as f64 * dt / 0.02).min(1.0);
        }
        let p = &self.profile;
        let mut factor = 1.0 + p.ripple * self.phasor.0 + p.wander * self.wander;
        for &(t0, len, frac) in &p.dips {
            if self.time >= t0 && self.time < t0 + len {
                factor -= frac * (std::f64::consts::PI * (self.time - t0) / len).sin();
            }
        }
        // Ripple and dips scale the speed but never reverse it.
        self.speed = self.base * TAU * factor.max(0.0);
        let da = self.speed * dt;
        self.angle += da;
        self.rotate(da);
    }

    /// Turns the (sin, cos) phasor by a small angle (Taylor to 5th order,
    /// exact to 1e-13 for the < 0.05 rad a tick turns), renormalised.
    fn rotate(&mut self, da: f64) {
        let d2 = da * da;
        // (reciprocals, not divisions: the phasor's chain carries into the
        // next tick's speed, and a division's latency held the whole loop)
        let (sd, cd) =
            (da * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0))), 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0)));
        let (s, c) = self.phasor;
        let (s, c) = (s * cd + c * sd, c * cd - s * sd);
        let norm = 1.5 - 0.5 * (s * s + c * c); // one Newton step toward |z| = 1
        self.phasor = (s * norm, c * norm);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_reaches_speed_holds_and_comes_to_rest() {
        let legs = vec![
            Leg { rpm: 600.0, accel_rpm_per_s: 1200.0, hold_s: 1.0 },
            Leg { rpm: 0.0, accel_rpm_per_s: 1200.0, hold_s: 0.1 },
        ];
        let mut l = Lathe::new(LatheProfile { start_rpm: 0.0, legs, ripple: 0.0, wander: 0.0, dips: vec![] }, 1);
        let dt = 1e-4;
        while !l.finished() {
            l.advance(dt);
        }
        assert_eq!(l.speed, 0.0);
        // 0.5 s up, 1 s at 10 rev/s, 0.5 s down: 2.5 + 10 + 2.5 = 15 revs
        assert!((l.angle / TAU - 15.0).abs() < 0.02, "{}", l.angle / TAU);
    }
}
