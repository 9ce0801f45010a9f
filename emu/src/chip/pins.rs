//! The outputs as the pins see them, for the safety checks.

use super::Chip;
use polyturn_stm32_model::addr::{off, TIM1_CCMR1, TIM1_CR1};
use polyturn_stm32_model::chip::gpio::{ALTERNATE, MODER};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outputs {
    pub tim1_cen: bool,
    pub oc1m: u32,
    /// PA8: TIM1's OC1 in AF mode (low when the timer does not drive it: the
    /// board's pull-down), else ODR
    pub step: Option<bool>,
    /// TIM10's compare in force (what PB8 follows) and the one waiting in
    /// its preload (from the next frame)
    pub esc_ccr1: u32,
    pub esc_waiting: u32,
    pub esc_stop: u32,
    pub enable: Option<bool>,
    pub enable_inactive: bool,
    pub x_step: Option<bool>,
}

impl Chip {
    pub fn outputs(&mut self) -> Outputs {
        let step =
            if self.gpio[0].field(MODER, 8) == ALTERNATE { Some(self.mcu.pa8()) } else { self.gpio[0].pin_out(8) };
        let t10 = &self.gp[3];
        let rate = self.rcc.apb2().1 / (t10.get(off::PSC) as u64 + 1);
        let frame_us = (t10.get(off::ARR) as u64 + 1) * 1_000_000 / rate.max(1);
        let psc = t10.get(off::PSC);
        Outputs {
            tim1_cen: self.mcu.read(TIM1_CR1) & 1 == 1,
            oc1m: self.mcu.read(TIM1_CCMR1) >> 4 & 7,
            step,
            // what the pin follows: the compare in force, not a preloaded one
            esc_ccr1: t10.active_ccr(0),
            esc_waiting: t10.get(off::CCR1),
            esc_stop: (stop_us(psc, frame_us) * rate / 1_000_000) as u32,
            enable: self.gpio[1].pin_out(13),
            enable_inactive: !polyturn_sync::Config::default().enable_active_high,
            x_step: self.gpio[1].pin_out(4),
        }
    }
}

/// The BLDC drive's stop for TIM10's prescaler and frame (`bldc-out`):
/// the RC ESCs' 1 000 µs stop pulse in a 20 or 2.5 ms frame at 1 µs counts
/// (PSC 95), OneShot125's 125 µs in a 500 µs frame at PSC 1 (a PWM's PSC
/// is 0 from 1 465 Hz up, so a 2 kHz PWM's frame is told apart); a PWM's
/// stop is no pulse at all.
fn stop_us(psc: u32, frame_us: u64) -> u64 {
    match (psc, frame_us) {
        (95, 20_000 | 2_500) => 1_000,
        (1, 500) => 125,
        _ => 0,
    }
}

impl Outputs {
    /// The step output stopped with STEP low, and the BLDC drive stopped:
    /// no pulse in force or the stop's (`bldcout::stop_ops` cuts the pulse
    /// under way: 0 in force to the frame's end), and the stop waiting.
    pub fn safe_now(&self) -> bool {
        let bldc = (self.esc_ccr1 == 0 || self.esc_ccr1 == self.esc_stop) && self.esc_waiting == self.esc_stop;
        !self.tim1_cen && self.step == Some(false) && bldc
    }

    pub fn safe_all(&self) -> bool {
        self.safe_now() && self.enable == Some(self.enable_inactive) && self.x_step == Some(false)
    }
}

impl std::fmt::Display for Outputs {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let b = |v: Option<bool>| v.map_or("-".to_string(), |v| (v as u8).to_string());
        write!(
            f,
            "TIM1 CEN={} OC1M={} STEP={}, TIM10 CCR1={} waiting {} (stop {}), ENABLE={} (inactive {}), X_STEP={}",
            self.tim1_cen as u8,
            self.oc1m,
            b(self.step),
            self.esc_ccr1,
            self.esc_waiting,
            self.esc_stop,
            b(self.enable),
            self.enable_inactive as u8,
            b(self.x_step)
        )
    }
}
