//! A BLDC spindle with its own encoder: inertia, a torque limit, the drive
//! between the firmware and the motor (`BldcDrive`), and a load torque
//! while an edge is cutting.
//!
//! What the firmware sends is an RC servo pulse (`polyturn_firmware::esc`:
//! 1 000 µs stop to 2 000 µs full speed, in whole µs) on TIM10, one every
//! 20 ms (50 Hz): the drive sees the pulse of the frame under way and holds
//! it until the next. A hobby ESC has no speed loop: the pulse sets the
//! motor's voltage, so its speed is the throttle's no-load speed less what
//! the load takes (the motor's speed-torque line), and it turns only the
//! way it is wired.

use std::f64::consts::TAU;

/// The drive between the firmware's command and the motor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BldcDrive {
    /// an RC ESC: throttle = the pulse's width, no speed loop; one pulse
    /// every `1 / frame_hz` (the firmware sends 50 Hz)
    RcEsc { frame_hz: f64 },
    /// a drive with its own speed loop (first order, `tau`), taking the
    /// pulse's speed every `1 / frame_hz`
    SpeedLoop { frame_hz: f64, tau: f64 },
    /// idealised (the simulator before issue 30): a speed loop taking every
    /// tick's command at full resolution; no real drive is fed so
    Ideal,
}

impl BldcDrive {
    /// What the firmware drives today: an RC ESC at 50 Hz.
    pub const FIRMWARE: BldcDrive = BldcDrive::RcEsc { frame_hz: 50.0 };
}

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
    pub drive: BldcDrive,
    /// rad/s at full throttle (2 000 µs) unloaded: the firmware's full
    /// scale (`max-rate`), as the machinist calibrates the ESC
    pub full_speed: f64,
    /// the speed the drive is holding (rad/s, signed as wired) and when the
    /// next frame comes (s)
    held: f64,
    next_frame: f64,
}

impl Bldc {
    pub fn new(counts_per_rev: u32) -> Bldc {
        Bldc {
            inertia: 2e-4,
            max_torque: 1.0,
            tau: 2e-3,
            cut_torque: 0.2,
            counts_per_rev,
            angle: 0.0,
            speed: 0.0,
            drive: BldcDrive::Ideal,
            full_speed: 1.0,
            held: 0.0,
            next_frame: 0.0,
        }
    }

    /// At `t`: the drive takes the firmware's command if a frame begins.
    /// `pulse_us` is the ESC pulse the firmware makes of it, `command` the
    /// speed it asked for (rad/s, signed), `wired` the way the motor turns
    /// (+1 or −1: a unidirectional ESC cannot reverse it).
    pub fn take(&mut self, t: f64, pulse_us: u16, command: f64, wired: f64) {
        let throttle = (pulse_us.saturating_sub(1000) as f64 / 1000.0).min(1.0);
        match self.drive {
            BldcDrive::Ideal => self.held = command,
            BldcDrive::RcEsc { frame_hz } | BldcDrive::SpeedLoop { frame_hz, .. } => {
                if t + 1e-12 >= self.next_frame {
                    self.held = throttle * self.full_speed * wired;
                    self.next_frame += 1.0 / frame_hz;
                }
            }
        }
    }

    /// The motor's torque from the drive (N·m) at its present speed.
    fn drive_torque(&self, enabled: bool) -> f64 {
        match self.drive {
            // throttle sets the voltage: torque falls linearly from stall
            // (max_torque) at standstill to 0 at the throttle's no-load
            // speed; the stop pulse freewheels
            BldcDrive::RcEsc { .. } if enabled && self.held != 0.0 => {
                let t = self.max_torque * (self.held - self.speed) / self.full_speed;
                // it drives only the way it is wired: no braking torque
                if t * self.held.signum() < 0.0 {
                    0.0
                } else {
                    t
                }
            }
            BldcDrive::RcEsc { .. } => 0.0,
            BldcDrive::SpeedLoop { tau, .. } if enabled => {
                (self.inertia * (self.held - self.speed) / tau).clamp(-self.max_torque, self.max_torque)
            }
            BldcDrive::Ideal if enabled => {
                (self.inertia * (self.held - self.speed) / self.tau).clamp(-self.max_torque, self.max_torque)
            }
            _ => 0.0,
        }
    }

    /// The encoder's count (the angle of count c is the middle of its interval).
    pub fn count(&self) -> i64 {
        (self.angle / TAU * self.counts_per_rev as f64).round() as i64
    }

    /// Runs the motor for `dt` on what the drive holds, with `cutting` load.
    pub fn advance(&mut self, cutting: bool, enabled: bool, dt: f64) {
        let torque = self.drive_torque(enabled);
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
