//! A BLDC spindle with its own encoder: inertia, a torque limit, the drive
//! between the firmware and the motor (`BldcDrive`), and a load torque
//! while an edge is cutting.
//!
//! What the firmware sends is TIM10's CCR1 in the frame `bldc-out` sets
//! up (`polyturn_firmware::bldcout::Out`: an RC pulse at 50 or 400 Hz,
//! OneShot125 at 2 kHz, or a PWM's duty), in whole timer counts: the drive
//! sees the command of the frame under way and holds it until the next.
//! A hobby ESC has no speed loop: the pulse sets the motor's voltage, so
//! its speed is the throttle's no-load speed less what the load takes (the
//! motor's speed-torque line), and it turns only the way it is wired. A
//! spindle driver's speed input feeds its own speed loop.

use polyturn_firmware::bldcout::Out;
use polyturn_sync::config::bldc_out::TIMER_HZ;
use polyturn_sync::config::BldcOut;
use polyturn_sync::{Config, ConfigError};
use std::f64::consts::TAU;

/// The drive between the firmware's command and the motor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BldcDrive {
    /// an RC ESC (`bldc-out esc50`, `esc400`, `oneshot125`): throttle =
    /// the pulse's place between stop and full, no speed loop
    RcEsc,
    /// a spindle driver's speed input (`bldc-out pwm`): its speed loop,
    /// first order `tau`, within the motor's torque
    SpeedLoop { tau: f64 },
    /// idealised: a speed loop taking every tick's command at full
    /// resolution; no real drive is fed so
    Ideal,
}

impl BldcDrive {
    /// What the default settings drive (`bldc-out esc50`): an RC ESC.
    pub const FIRMWARE: BldcDrive = BldcDrive::RcEsc;
}

/// The simulated spindle's inertia, motor and cutter.
pub const INERTIA_KG_M2: f64 = 2e-4;

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
            inertia: INERTIA_KG_M2,
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
    /// `ccr` is TIM10's CCR1 the firmware makes of it in `out`'s frame,
    /// `command` the speed it asked for (rad/s, signed), `wired` the way
    /// the motor turns (+1 or −1: the firmware drives it no other way).
    pub fn take(&mut self, t: f64, ccr: u32, out: &Out, command: f64, wired: f64) {
        if self.drive == BldcDrive::Ideal {
            self.held = command;
        } else if t + 1e-12 >= self.next_frame {
            let throttle = (ccr.saturating_sub(out.stop) as f64 / out.span.max(1) as f64).min(1.0);
            self.held = throttle * self.full_speed * wired;
            self.next_frame += (out.psc + 1) as f64 * (out.arr + 1) as f64 / TIMER_HZ as f64;
        }
    }

    /// The motor's torque from the drive (N·m) at its present speed.
    fn drive_torque(&self, enabled: bool) -> f64 {
        match self.drive {
            // throttle sets the voltage: torque falls linearly from stall
            // (max_torque) at standstill to 0 at the throttle's no-load
            // speed; the stop pulse freewheels
            BldcDrive::RcEsc if enabled && self.held != 0.0 => {
                let t = self.max_torque * (self.held - self.speed) / self.full_speed;
                // it drives only the way it is wired: no braking torque
                if t * self.held.signum() < 0.0 {
                    0.0
                } else {
                    t
                }
            }
            BldcDrive::RcEsc => 0.0,
            BldcDrive::SpeedLoop { tau } if enabled => {
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

/// A spindle driver's speed loop, as the simulator models the drives fed
/// by `bldc-out pwm` (a modest one: ER11 spindle drivers' loops are
/// slower, not faster).
pub const SPINDLE_TAU_S: f64 = 2e-3;

/// The drive the simulator puts behind `out`.
fn drive_for(out: BldcOut) -> BldcDrive {
    if out == BldcOut::Pwm {
        BldcDrive::SpeedLoop { tau: SPINDLE_TAU_S }
    } else {
        BldcDrive::RcEsc
    }
}

/// The full speed the firmware scales its command to (`max-rate` counts/s
/// of the motor's encoder), rad/s.
pub fn full_speed(sc: &super::Scenario) -> f64 {
    sc.core.max_step_rate_hz as f64 / sc.core.motor_steps_per_rev.max(1) as f64 * TAU
}

/// The time constant of the drive behind `out`, ms, as the bench
/// procedure measures it: the speed loop's, or an ESC's motor's (inertia ×
/// full speed / stall torque), rounded, at least 1.
pub fn own_tau_ms(sc: &super::Scenario, out: BldcOut) -> u32 {
    let own_s = match drive_for(out) {
        BldcDrive::SpeedLoop { tau } => tau,
        _ => INERTIA_KG_M2 * full_speed(sc) / sc.bldc_max_torque,
    };
    (own_s * 1e3).round().clamp(1.0, u32::MAX as f64) as u32
}

/// `sc` fed through `out`: the drive the simulator puts behind it (an RC
/// ESC, or a spindle driver's speed loop for `pwm`) and the firmware's
/// settings for it. `bldc-tau` is the drive's own time constant unless
/// given, as the bench procedure measures it: the speed loop's, or an
/// ESC's motor's (inertia × full speed / stall torque).
pub fn fit_drive(sc: &mut super::Scenario, out: BldcOut, pwm_hz: u32, tau_ms: Option<u32>) -> Result<(), ConfigError> {
    let drive = drive_for(out);
    let tau = tau_ms.unwrap_or(own_tau_ms(sc, out));
    // set together and checked once: a drive too slow for the job is then
    // named as `bldc-out`, the rule's own name, whichever field moved
    let c = Config { bldc_out: out, pwm_hz, bldc_tau_ms: tau, ..sc.core };
    c.validate()?;
    sc.core = c;
    sc.bldc_drive = drive;
    Ok(())
}
