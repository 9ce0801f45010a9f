//! The BLDC drive's interface: what TIM10_CH1 (PB8) sends the
//! drive and how often the drive takes a new command, and the drive's own
//! time constant. The phase loop's gains come from both (`BldcGains`); the
//! register words are the firmware's (`polyturn_firmware::bldcout`).

use super::table::{BLDC_OUT, PWM_HZ};
use super::{range, ConfigError};
use crate::timing::Timing;

/// What the BLDC drive is fed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BldcOut {
    /// an RC ESC: 1 000..2 000 µs every 20 ms (a servo's rate)
    Esc50,
    /// an RC ESC taking the same pulse every 2.5 ms
    Esc400,
    /// OneShot125: 125..250 µs every 500 µs
    OneShot125,
    /// a spindle driver's speed input: duty 0..100 % at `pwm-hz`, and the
    /// sense on BLDC_DIR (PB1)
    Pwm,
}

/// TIM10's kernel clock: the APB2 timer clock (RM0383 §6.2, figure 12),
/// which `polyturn_firmware::clocks` makes exactly this.
pub const TIMER_HZ: u32 = Timing::FIRMWARE.step_timer_hz;

pub const RATE: &str = "does not fit with the others: the drive must take a command at least once per cutter revolution at max-rpm (max-rpm x ratio / 60 <= 50 Hz for esc50, 400 for esc400, 2000 for oneshot125, pwm-hz for pwm)";

impl BldcOut {
    pub const ALL: [BldcOut; 4] = [BldcOut::Esc50, BldcOut::Esc400, BldcOut::OneShot125, BldcOut::Pwm];

    pub fn name(self) -> &'static str {
        match self {
            BldcOut::Esc50 => "esc50",
            BldcOut::Esc400 => "esc400",
            BldcOut::OneShot125 => "oneshot125",
            BldcOut::Pwm => "pwm",
        }
    }

    pub fn parse(v: &str) -> Result<BldcOut, ConfigError> {
        let v = v.trim();
        BldcOut::ALL.into_iter().find(|o| o.name() == v).ok_or(range("bldc-out", BLDC_OUT))
    }

    /// The saved byte (`codec::ext`).
    pub fn code(self) -> u8 {
        self as u8
    }

    pub fn from_code(b: u8) -> Option<BldcOut> {
        BldcOut::ALL.get(b as usize).copied()
    }

    /// How many new commands the drive takes per second: one per frame.
    pub fn frame_hz(self, pwm_hz: u32) -> u32 {
        match self {
            BldcOut::Esc50 => 50,
            BldcOut::Esc400 => 400,
            BldcOut::OneShot125 => 2_000,
            BldcOut::Pwm => pwm_hz,
        }
    }
}

/// TIM10's prescaler for a PWM at `hz`: the smallest that fits the period
/// in the 16-bit ARR (TIM10_ARR, §14.5.9), so the duty has the most steps.
pub fn pwm_prescaler(hz: u32) -> u32 {
    (TIMER_HZ / hz.max(1)).div_ceil(1 << 16).max(1) - 1
}

/// `pwm-hz` alone: in range, and a period of whole timer counts (the timer
/// cannot make any other frequency).
pub fn check_pwm_hz(hz: u32) -> Result<(), ConfigError> {
    let span = PWM_HZ;
    if !span.contains(hz) || !TIMER_HZ.is_multiple_of((pwm_prescaler(hz) + 1) * hz) {
        return Err(span.error());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_interface_round_trips_its_name_and_code() {
        for o in BldcOut::ALL {
            assert_eq!(BldcOut::parse(o.name()), Ok(o));
            assert_eq!(BldcOut::from_code(o.code()), Some(o));
        }
        assert_eq!(BldcOut::from_code(4), None);
        assert_eq!(BldcOut::parse("esc").unwrap_err().field, "bldc-out");
    }

    #[test]
    fn the_timer_makes_exactly_the_pwm_frequencies_it_takes() {
        for hz in [1_000, 2_000, 3_000, 4_000, 5_000, 8_000, 10_000, 12_000, 16_000, 20_000] {
            assert_eq!(check_pwm_hz(hz), Ok(()), "{hz}");
            let counts = TIMER_HZ / (pwm_prescaler(hz) + 1) / hz;
            assert!((4_800..=1 << 16).contains(&counts), "{hz}: {counts} counts a period");
            assert_eq!(TIMER_HZ / (pwm_prescaler(hz) + 1) / counts, hz);
        }
        // 96 MHz / 7 kHz and / 9 kHz are no whole number of counts
        for hz in [999, 7_000, 9_000, 20_001, 0] {
            assert_eq!(check_pwm_hz(hz).unwrap_err().field, "pwm-hz", "{hz}");
        }
        assert_eq!(pwm_prescaler(1_000), 1, "96 000 counts would not fit ARR");
        assert_eq!(pwm_prescaler(2_000), 0);
    }
}
