//! A BLDC spindle with its own encoder: inertia, a torque limit, an ESC
//! speed loop (first order), and a load torque while an edge is cutting.

use std::f64::consts::TAU;

#[derive(Clone, Debug)]
pub struct Bldc {
    /// kg·m²
    pub inertia: f64,
    /// N·m
    pub max_torque: f64,
    /// s: the ESC's speed-loop time constant
    pub tau: f64,
    /// N·m while an edge is in the cut
    pub cut_torque: f64,
    pub counts_per_rev: u32,
    pub angle: f64,
    pub speed: f64,
}

impl Bldc {
    pub fn new(counts_per_rev: u32) -> Bldc {
        Bldc { inertia: 2e-4, max_torque: 1.0, tau: 2e-3, cut_torque: 0.2, counts_per_rev, angle: 0.0, speed: 0.0 }
    }

    /// The encoder's count (the angle of count c is the middle of its interval).
    pub fn count(&self) -> i64 {
        (self.angle / TAU * self.counts_per_rev as f64).round() as i64
    }

    /// Applies a speed command (rad/s) for `dt`, with `cutting` load.
    pub fn advance(&mut self, command: f64, cutting: bool, enabled: bool, dt: f64) {
        let wanted = if enabled { self.inertia * (command - self.speed) / self.tau } else { 0.0 };
        let torque = wanted.clamp(-self.max_torque, self.max_torque);
        // Bearing drag: viscous (τ = J/b = 0.4 s) plus a little Coulomb, so a
        // coasting spindle comes to rest as a real one does.
        // (f64::signum(0.0) is 1.0, so friction at rest is set to 0 by hand.)
        let coulomb = if self.speed == 0.0 { 0.0 } else { 0.005 * self.speed.signum() };
        let drag = 5e-4 * self.speed + coulomb;
        let load = drag + if cutting && self.speed != 0.0 { self.cut_torque * self.speed.signum() } else { 0.0 };
        let accel = (torque - load) / self.inertia;
        let before = self.speed;
        self.speed += accel * dt;
        if !enabled && before.signum() != self.speed.signum() {
            self.speed = 0.0; // coasting to rest never reverses it
        }
        self.angle += 0.5 * (before + self.speed) * dt;
    }
}
