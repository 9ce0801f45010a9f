//! One validated `Config`: every field's unit is in its name, every error
//! names the field (as the console spells it) and its allowed range, and an
//! invalid change leaves the settings as they were.

use crate::console::number::unsigned;
use crate::ratio::{Ratio, RatioError};

pub mod bldc_out;
pub mod table;
pub mod together;
pub use bldc_out::BldcOut;
use table::*;
pub use table::{Span, NAMES, SETTINGS};
pub use together::{Misfit, Rule, SetError};

/// Relative sense of rotation (see the geometry model for the convention:
/// "same" = both spindles turn the same way seen from the same end).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Sense {
    Same,
    Opposite,
}

/// What drives the cutter spindle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DriveKind {
    /// step/dir: a stepper or a servo taking step/dir
    Stepper,
    /// a velocity-driven spindle with its own encoder
    Bldc,
    /// no rotating cutter: a single-point tool on the X cam (the note on
    /// noncircular turning); the gear still runs, its output stays off
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// lathe encoder counts per lathe revolution (after ×4 decoding)
    pub encoder_counts_per_rev: u32,
    /// motor steps (or cutter-encoder counts) per cutter revolution
    pub motor_steps_per_rev: u32,
    pub ratio: Ratio,
    pub sense: Sense,
    pub edges: u8,
    pub max_step_rate_hz: u32,
    pub max_accel_steps_per_s2: u32,
    pub following_error_limit_steps: u32,
    /// phase offset of the cutter, in millidegrees of the cutter
    pub phase_offset_mdeg: i32,
    pub drive: DriveKind,
    pub dir_setup_ns: u32,
    pub step_pulse_ns: u32,
    pub enable_active_high: bool,
    /// the fastest the lathe can turn: above it, encoder jumps are implausible
    pub max_lathe_rpm: u32,
    /// counts per cutter revolution (after ×4 decoding) of an encoder on a
    /// stepper's or step/dir servo's shaft, on TIM4: the lost-step alarm
    /// compares it with the steps sent. 0: none (no alarm)
    pub cutter_encoder_cpr: u32,
    /// how far, in motor steps, the shaft may be from the steps sent before
    /// the `lost-steps` fault (with a cutter encoder)
    pub lost_step_limit_steps: u32,
    /// while following, a change of speed the cutter may make at once
    /// between speeds within it (its motor's start rate, below the pull-in
    /// rate with the cutter's inertia), steps/s; 0: every change at
    /// `max-accel` (a stop ramps at `max-accel` whatever it is)
    pub start_rate_hz: u32,
    /// what the BLDC drive is fed (`drive bldc`)
    pub bldc_out: BldcOut,
    /// the PWM's frequency with `bldc-out pwm`
    pub pwm_hz: u32,
    /// the BLDC drive's time constant: its speed loop's, or an RC ESC's
    /// motor's (time to 63 % of a step in command, unloaded)
    pub bldc_tau_ms: u32,
}

/// A refused value: the field and the allowed range, for one error line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConfigError {
    pub field: &'static str,
    pub allowed: &'static str,
}

impl Default for Config {
    /// A 600-line (2400-count) lathe encoder, a 200-step motor at 1/16, 2:1.
    fn default() -> Config {
        Config {
            encoder_counts_per_rev: 2400,
            motor_steps_per_rev: 3200,
            ratio: Ratio::TWO,
            sense: Sense::Same,
            edges: 3,
            max_step_rate_hz: 200_000,
            max_accel_steps_per_s2: 400_000,
            following_error_limit_steps: 64,
            phase_offset_mdeg: 0,
            drive: DriveKind::Stepper,
            dir_setup_ns: 5_000,
            step_pulse_ns: 2_000,
            enable_active_high: false,
            max_lathe_rpm: 1500,
            cutter_encoder_cpr: 0,
            // two full steps of a 200-step motor at 1/16: a loaded rotor
            // lags by up to one before it slips, and a slip loses four
            lost_step_limit_steps: 32,
            // off until the machinist has found the motor's start rate
            // (the bench procedure): a start faster than the motor can pull
            // in loses steps
            start_rate_hz: 0,
            // what the firmware sent before there was a choice
            bldc_out: BldcOut::Esc50,
            pwm_hz: 1_000,
            // a slow guess: a loop tuned for a slower drive than the real
            // one is stable, only slower to correct
            bldc_tau_ms: 20,
        }
    }
}

const fn range(field: &'static str, allowed: &'static str) -> ConfigError {
    ConfigError { field, allowed }
}

impl Config {
    /// True if `self` and `other` differ at most in the phase offset (the
    /// only setting that may change while running).
    pub fn differs_only_in_phase(&self, other: &Config) -> bool {
        Config { phase_offset_mdeg: other.phase_offset_mdeg, ..*self } == *other
    }

    /// Checks every field and the cross-field limits.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_fields()?;
        self.validate_together()
    }

    /// Each field in its own range.
    fn validate_fields(&self) -> Result<(), ConfigError> {
        CPR.check(self.encoder_counts_per_rev)?;
        STEPS.check(self.motor_steps_per_rev)?;
        EDGES.check(self.edges as u32)?;
        MAX_RATE.check(self.max_step_rate_hz)?;
        MAX_ACCEL.check(self.max_accel_steps_per_s2)?;
        FERROR.check(self.following_error_limit_steps)?;
        if self.phase_offset_mdeg.unsigned_abs() > 360_000 {
            return Err(range("phase", PHASE));
        }
        DIR_SETUP.check(self.dir_setup_ns)?;
        PULSE.check(self.step_pulse_ns)?;
        MAX_RPM.check(self.max_lathe_rpm)?;
        if self.cutter_encoder_cpr != 0 {
            CUTTER_CPR.check(self.cutter_encoder_cpr)?;
        }
        LOST_STEPS.check(self.lost_step_limit_steps)?;
        START_RATE.check(self.start_rate_hz)?;
        bldc_out::check_pwm_hz(self.pwm_hz)?;
        BLDC_TAU.check(self.bldc_tau_ms).map(|_| ())
    }

    /// The limits that join several settings (`together::Rule`). The
    /// error names one of them (`with` names the one being set) and says
    /// which others take part.
    fn validate_together(&self) -> Result<(), ConfigError> {
        match Rule::ALL.into_iter().find(|r| !r.holds(self)) {
            Some(r) => Err(r.error()),
            None => Ok(()),
        }
    }

    /// Steps the motor needs per second at `lathe_rpm` (planning, host).
    pub fn motor_rate_at(&self, lathe_rpm: f64) -> f64 {
        lathe_rpm / 60.0 * self.ratio.to_f64() * self.motor_steps_per_rev as f64
    }

    /// Applies `set <name> <value>` to a copy; the original is untouched
    /// unless the whole result validates.
    pub fn with(&self, name: &str, value: &str) -> Result<Config, ConfigError> {
        self.try_with(name, value).map_err(SetError::error)
    }

    /// `with`, a value that does not fit with the others refused as a
    /// `Misfit`: the setting, the rule, and the settings it would have
    /// made, from which the console states the setting's bound.
    pub fn try_with(&self, name: &str, value: &str) -> Result<Config, SetError> {
        let c = self.assigned(name, value)?;
        c.validate_fields()?;
        // Valid alone but not with the others: name the setting being set,
        // not the one the check happens to be written for (`set steps
        // 8000` is too fast because of the steps, as the machinist sees it).
        // (`assigned` took the name: it is one of `NAMES`)
        let setting = NAMES.iter().find(|n| **n == name).copied().unwrap_or("name");
        match Misfit::of(setting, &c) {
            Some(m) => Err(SetError::Together(m)),
            None => Ok(c),
        }
    }

    /// A copy with `name` set to `value`, parsed but not yet validated.
    fn assigned(&self, name: &str, value: &str) -> Result<Config, ConfigError> {
        let mut c = *self;
        let num = |s: Span| unsigned(value.trim()).ok_or(s.error());
        match name {
            "cpr" => c.encoder_counts_per_rev = num(CPR)?,
            "steps" => c.motor_steps_per_rev = num(STEPS)?,
            "ratio" => c.ratio = Ratio::parse(value).map_err(ratio_error)?,
            "dir" => c.sense = parse_sense(value)?,
            "edges" => c.edges = num(EDGES)?.min(255) as u8,
            "max-rate" => c.max_step_rate_hz = num(MAX_RATE)?,
            "max-accel" => c.max_accel_steps_per_s2 = num(MAX_ACCEL)?,
            "ferror" => c.following_error_limit_steps = num(FERROR)?,
            "phase" => c.phase_offset_mdeg = parse_mdeg(value)?,
            "drive" => c.drive = parse_drive(value)?,
            "dir-setup" => c.dir_setup_ns = num(DIR_SETUP)?,
            "pulse" => c.step_pulse_ns = num(PULSE)?,
            "enable" => c.enable_active_high = parse_polarity(value)?,
            "max-rpm" => c.max_lathe_rpm = num(MAX_RPM)?,
            "cutter-cpr" => c.cutter_encoder_cpr = parse_cutter_cpr(value)?,
            "lost-steps" => c.lost_step_limit_steps = num(LOST_STEPS)?,
            "start-rate" => c.start_rate_hz = num(START_RATE)?,
            "bldc-out" => c.bldc_out = BldcOut::parse(value)?,
            "pwm-hz" => c.pwm_hz = num(PWM_HZ)?,
            "bldc-tau" => c.bldc_tau_ms = num(BLDC_TAU)?,
            _ => return Err(range("name", "one of: cpr steps ratio dir edges max-rate max-accel ferror phase drive dir-setup pulse enable max-rpm cutter-cpr lost-steps start-rate bldc-out pwm-hz bldc-tau")),
        }
        Ok(c)
    }
}

fn ratio_error(e: RatioError) -> ConfigError {
    range("ratio", e.describe())
}

fn parse_sense(v: &str) -> Result<Sense, ConfigError> {
    match v.trim() {
        "same" => Ok(Sense::Same),
        "opposite" => Ok(Sense::Opposite),
        _ => Err(range("dir", DIR)),
    }
}

fn parse_drive(v: &str) -> Result<DriveKind, ConfigError> {
    match v.trim() {
        "stepper" => Ok(DriveKind::Stepper),
        "bldc" => Ok(DriveKind::Bldc),
        "none" => Ok(DriveKind::None),
        _ => Err(range("drive", DRIVE)),
    }
}

/// `off` (no cutter encoder) or a count (its range: `validate_fields`); 0
/// is refused as a count (`off` says it).
fn parse_cutter_cpr(v: &str) -> Result<u32, ConfigError> {
    match v.trim() {
        "off" => Ok(0),
        n => unsigned(n).filter(|&n| n != 0).ok_or(CUTTER_CPR.error()),
    }
}

fn parse_polarity(v: &str) -> Result<bool, ConfigError> {
    match v.trim() {
        "high" => Ok(true),
        "low" => Ok(false),
        _ => Err(range("enable", ENABLE)),
    }
}

/// Degrees with up to three decimals, e.g. `-12.5`, as millidegrees.
fn parse_mdeg(v: &str) -> Result<i32, ConfigError> {
    degrees_mdeg(v, 360_000).ok_or(range("phase", PHASE))
}

/// Degrees with up to three decimals as millidegrees, at most `max_mdeg`
/// either way (`phase`, and the console's `jog`).
pub fn degrees_mdeg(v: &str, max_mdeg: i32) -> Option<i32> {
    let v = v.trim();
    let (neg, body) = match v.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, v),
    };
    // `12`, `12.5`, `0.125` as the documents write them: the whole part
    // an unsigned number (no `+`, no leading zero), any decimals digits
    let (whole, frac) = match body.split_once('.') {
        Some((w, f)) => (w, Some(f)),
        None => (body, None),
    };
    let w = i32::try_from(unsigned(whole)?).ok()?;
    let frac = frac.unwrap_or("000");
    if frac.is_empty() || frac.len() > 3 || !frac.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let mut f = frac.bytes().fold(0, |f, b| f * 10 + i32::from(b - b'0'));
    for _ in frac.len()..3 {
        f *= 10;
    }
    let mdeg = w.checked_mul(1000).and_then(|x| x.checked_add(f))?;
    if mdeg > max_mdeg {
        return None;
    }
    Some(if neg { -mdeg } else { mdeg })
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod with_tests;
