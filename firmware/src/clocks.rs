//! The board's clock tree, as numbers: the one place the timer clock the
//! sync core plans with comes from. `app::clocks` gives embassy these same
//! divisors (checked at compile time there), and `Timing::FIRMWARE`, which
//! the simulator, the fake board, the page and the sync core's tests all
//! use, must equal what this tree makes (the assertion below fails the
//! build of every crate that links this one if they differ).

use polyturn_sync::Timing;

/// The PLL and bus dividers (RM0383 §6.3.2 RCC_PLLCFGR, §6.3.3 RCC_CFGR).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Clocks {
    /// the crystal on the Black Pill (HSE)
    pub hse_hz: u32,
    /// PLLM: the VCO's input is HSE / M, 1 to 2 MHz (2 MHz limits jitter)
    pub pll_m: u32,
    /// PLLN: VCO = input × N, 100 to 432 MHz
    pub pll_n: u32,
    /// PLLP (2, 4, 6 or 8): SYSCLK = VCO / P
    pub pll_p: u32,
    /// PLLQ: the 48 MHz USB clock = VCO / Q
    pub pll_q: u32,
    /// HPRE, PPRE1, PPRE2 as divisors
    pub ahb_div: u32,
    pub apb1_div: u32,
    pub apb2_div: u32,
}

/// 25 MHz HSE → 1 MHz → VCO 192 MHz → SYSCLK 96 MHz, USB 48 MHz; APB1 at
/// 48 MHz (its limit is 50 MHz, DS10314 §3.15) and APB2 at 96 MHz.
pub const CLOCKS: Clocks =
    Clocks { hse_hz: 25_000_000, pll_m: 25, pll_n: 192, pll_p: 2, pll_q: 4, ahb_div: 1, apb1_div: 2, apb2_div: 1 };

impl Clocks {
    /// f(VCO) = f(PLL input) × PLLN / PLLM (RM0383 §6.3.2).
    pub const fn vco_hz(&self) -> u32 {
        self.hse_hz / self.pll_m * self.pll_n
    }
    pub const fn sysclk_hz(&self) -> u32 {
        self.vco_hz() / self.pll_p
    }
    pub const fn usb_hz(&self) -> u32 {
        self.vco_hz() / self.pll_q
    }
    pub const fn hclk_hz(&self) -> u32 {
        self.sysclk_hz() / self.ahb_div
    }
    /// TIM2-5 (APB1) and TIM1, 9-11 (APB2) run at the bus clock when its
    /// prescaler is 1, at twice it otherwise (RM0383 §6.2, "the timer
    /// clock frequencies are automatically set by hardware"; TIMPRE in
    /// RCC_DCKCFGR left at reset; efton.sk STM32 gotcha 2).
    pub const fn timer_hz(&self, apb_div: u32) -> u32 {
        let pclk = self.hclk_hz() / apb_div;
        if apb_div == 1 {
            pclk
        } else {
            2 * pclk
        }
    }
    pub const fn apb1_timer_hz(&self) -> u32 {
        self.timer_hz(self.apb1_div)
    }
    pub const fn apb2_timer_hz(&self) -> u32 {
        self.timer_hz(self.apb2_div)
    }
}

/// The tick and the step timer's clock, from this tree. The control tick
/// runs at 20 kHz (50 µs), the floor of the design: the tick and its step
/// plan must fit its period (4 800 cycles) on the emulator's bound of the
/// cycles the STM32F411 spends (`emu`).
pub const TIMING: Timing = Timing { tick_hz: 20_000, step_timer_hz: CLOCKS.apb2_timer_hz() };

// One timing: what the host plans with is what the board makes. TIM1 (the
// steps, APB2) and TIM2/TIM3 (APB1) must share the clock, since the step
// count (TIM2) and the lathe's (TIM3) are read against TIM1's cycles.
const _: () = {
    assert!(TIMING.tick_hz == Timing::FIRMWARE.tick_hz);
    assert!(TIMING.step_timer_hz == Timing::FIRMWARE.step_timer_hz);
    assert!(CLOCKS.apb1_timer_hz() == CLOCKS.apb2_timer_hz());
    assert!(CLOCKS.usb_hz() == 48_000_000);
    assert!(CLOCKS.sysclk_hz() <= 100_000_000);
    assert!(CLOCKS.hclk_hz() / CLOCKS.apb1_div <= 50_000_000);
    assert!(CLOCKS.hclk_hz() / CLOCKS.apb2_div <= 100_000_000);
    // the PLL's own ranges (RM0383 §6.3.2 RCC_PLLCFGR): an exact VCO input
    // of 1 to 2 MHz, a VCO of 100 to 432 MHz, P one of 2, 4, 6, 8, Q >= 2
    assert!(CLOCKS.hse_hz.is_multiple_of(CLOCKS.pll_m) && CLOCKS.vco_hz().is_multiple_of(CLOCKS.pll_p));
    assert!(CLOCKS.hse_hz / CLOCKS.pll_m >= 1_000_000 && CLOCKS.hse_hz / CLOCKS.pll_m <= 2_000_000);
    assert!(CLOCKS.vco_hz() >= 100_000_000 && CLOCKS.vco_hz() <= 432_000_000);
    assert!(matches!(CLOCKS.pll_p, 2 | 4 | 6 | 8) && CLOCKS.pll_q >= 2);
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_black_pill_tree_gives_96_mhz_timers_and_48_mhz_usb() {
        assert_eq!(CLOCKS.vco_hz(), 192_000_000);
        assert_eq!(CLOCKS.sysclk_hz(), 96_000_000);
        assert_eq!(CLOCKS.usb_hz(), 48_000_000);
        assert_eq!(CLOCKS.apb1_timer_hz(), 96_000_000, "APB1 at 48 MHz, its timers twice that");
        assert_eq!(CLOCKS.apb2_timer_hz(), 96_000_000);
    }

    #[test]
    fn a_timer_on_an_undivided_bus_runs_at_the_bus_clock_and_doubles_otherwise() {
        let c = Clocks { apb1_div: 4, apb2_div: 1, ..CLOCKS };
        assert_eq!(c.apb1_timer_hz(), 48_000_000);
        assert_eq!(c.apb2_timer_hz(), 96_000_000);
        assert_eq!(Clocks { ahb_div: 2, ..c }.apb2_timer_hz(), 48_000_000);
    }

    #[test]
    fn the_timing_everyone_plans_with_is_the_boards() {
        assert_eq!(TIMING, Timing::FIRMWARE);
        assert_eq!(TIMING.tick_hz, crate::board::TICK_HZ);
        let cycles = Timing::FIRMWARE.step_timer_hz / Timing::FIRMWARE.tick_hz;
        assert_eq!(
            cycles * Timing::FIRMWARE.tick_hz,
            Timing::FIRMWARE.step_timer_hz,
            "a whole number of cycles a tick"
        );
    }
}
