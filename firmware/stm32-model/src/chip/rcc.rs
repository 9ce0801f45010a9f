//! RCC (RM0383 §6), PWR (§5) and the flash interface's registers (§3.8), enough
//! for embassy's clock setup. Oscillators and the PLL are ready as soon as they are
//! switched on (the firmware only polls the flags; start-up times are not modelled).
//! The clock tree is computed from what the firmware wrote, with the Black Pill's
//! 25 MHz HSE crystal.

use super::RegFile;

/// §6.2.2: the internal RC oscillator.
pub const HSI_HZ: u64 = 16_000_000;
/// The WeAct Black Pill's crystal.
pub const HSE_HZ: u64 = 25_000_000;

pub const CR: u32 = 0x00;
pub const PLLCFGR: u32 = 0x04;
pub const CFGR: u32 = 0x08;
pub const CSR: u32 = 0x74;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rcc {
    pub regs: RegFile,
}

impl Default for Rcc {
    /// Reset values: CR HSION|HSIRDY|HSITRIM=16 (§6.3.1), PLLCFGR (§6.3.2), CSR's
    /// PORRSTF|PINRSTF|BORRSTF (§6.3.21).
    fn default() -> Rcc {
        Rcc { regs: RegFile::new(&[(CR, 0x0000_0083), (PLLCFGR, 0x2400_3010), (CSR, 0x0E00_0000)]) }
    }
}

impl Rcc {
    pub fn read(&self, off: u32) -> u32 {
        let v = self.regs.get(off);
        match off {
            // §6.3.1: HSIRDY, HSERDY, PLLRDY, PLLI2SRDY follow HSION, HSEON, PLLON, PLLI2SON
            CR => [0u32, 16, 24, 26]
                .iter()
                .fold(v & !(1 << 1 | 1 << 17 | 1 << 25 | 1 << 27), |a, on| a | (v >> on & 1) << (on + 1)),
            CFGR => v & !0xC | (self.source() as u32) << 2, // §6.3.3: SWS, the clock in use
            CSR => v & !2 | (v & 1) << 1,                   // §6.3.21: LSIRDY follows LSION
            _ => v,
        }
    }

    pub fn write(&mut self, off: u32, value: u32, mask: u32) {
        if off == CSR && value & mask & 1 << 24 != 0 {
            // §6.3.21: RMVF clears the reset flags
            self.regs.set(CSR, self.regs.get(CSR) & 0x00FF_FFFF);
            return;
        }
        self.regs.write(off, value, mask);
    }

    /// The PLL's P output (§6.3.2: VCO = source · N / M, P = 2, 4, 6, 8), 0 while off.
    pub fn pll_p(&self) -> u64 {
        let c = self.regs.get(PLLCFGR);
        let src = if c >> 22 & 1 == 1 { HSE_HZ } else { HSI_HZ };
        let (m, n, p) = (c as u64 & 0x3F, (c as u64 >> 6) & 0x1FF, 2 * ((c as u64 >> 16 & 3) + 1));
        if m == 0 || self.regs.get(CR) >> 24 & 1 == 0 {
            return 0;
        }
        src * n / m / p
    }

    /// The clock in use: CFGR.SW once its source is on, else HSI (§6.2.6 "clock
    /// source switching": a switch waits until the target clock is ready; from
    /// reset the system runs on HSI).
    fn source(&self) -> u64 {
        let sw = self.regs.get(CFGR) as u64 & 3;
        let ready = match sw {
            1 => self.regs.get(CR) >> 16 & 1 == 1,
            2 => self.pll_p() > 0,
            _ => true,
        };
        if ready && sw < 3 {
            sw
        } else {
            0
        }
    }

    /// SYSCLK from the clock in use (§6.3.3 SW/SWS): HSI, HSE or the PLL.
    pub fn sysclk(&self) -> u64 {
        match self.source() {
            0 => HSI_HZ,
            1 => HSE_HZ,
            _ => self.pll_p(),
        }
    }

    /// HCLK: SYSCLK / HPRE (§6.3.3: 0xxx none, 1000 = 2 ... 1111 = 512; 32 is skipped).
    pub fn hclk(&self) -> u64 {
        let hpre = self.regs.get(CFGR) >> 4 & 0xF;
        let div = if hpre < 8 { 1 } else { [2, 4, 8, 16, 64, 128, 256, 512][hpre as usize - 8] };
        self.sysclk() / div
    }

    fn apb(&self, shift: u32) -> (u64, u64) {
        let ppre = self.regs.get(CFGR) >> shift & 7;
        let div = if ppre < 4 { 1 } else { 2u64 << (ppre - 4) };
        let pclk = self.hclk() / div;
        // §6.2 "the timer clock frequencies are automatically set by hardware": PCLK
        // when the APB prescaler is 1, otherwise twice PCLK
        (pclk, if div == 1 { pclk } else { 2 * pclk })
    }

    /// (PCLK1, timer clock of APB1) from PPRE1 (§6.3.3 bits 12:10).
    pub fn apb1(&self) -> (u64, u64) {
        self.apb(10)
    }

    /// (PCLK2, timer clock of APB2) from PPRE2 (§6.3.3 bits 15:13).
    pub fn apb2(&self) -> (u64, u64) {
        self.apb(13)
    }
}

/// PWR (§5.4): CR's VOS resets to scale 2 (§5.4.1); CSR.VOSRDY (§5.4.2) reads 1 once
/// the PLL is on (the scale is applied when the PLL starts).
pub fn pwr_read(regs: &RegFile, rcc: &Rcc, off: u32) -> u32 {
    let v = regs.get(off);
    if off == 0x04 {
        return v & !(1 << 14) | (rcc.regs.get(CR) >> 24 & 1) << 14;
    }
    v
}

pub fn pwr_reset() -> RegFile {
    RegFile::new(&[(0x00, 0x0000_8000)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_black_pill_tree_gives_96_mhz_and_apb1_timers_at_twice_pclk1() {
        let mut r = Rcc::default();
        assert_eq!(r.sysclk(), HSI_HZ, "§6.2.2: HSI after reset");
        // PLL from HSE: M = 25, N = 192, P = 2 -> 96 MHz; PPRE1 = /2, PPRE2 = /1
        r.write(PLLCFGR, 1 << 22 | 25 | 192 << 6, u32::MAX);
        r.write(CR, 1 << 16 | 1 << 24, 1 << 16 | 1 << 24);
        assert_eq!(r.read(CR) >> 25 & 1, 1, "PLLRDY follows PLLON");
        r.write(CFGR, 2 | 0b100 << 10, u32::MAX);
        assert_eq!(r.read(CFGR) >> 2 & 3, 2, "SWS follows SW");
        assert_eq!(r.sysclk(), 96_000_000);
        assert_eq!(r.apb1(), (48_000_000, 96_000_000));
        assert_eq!(r.apb2(), (96_000_000, 96_000_000));
    }

    #[test]
    fn a_switch_to_a_pll_that_is_off_keeps_hsi() {
        let mut r = Rcc::default();
        r.write(CFGR, 2, u32::MAX);
        assert_eq!((r.read(CFGR) >> 2 & 3, r.sysclk()), (0, HSI_HZ), "§6.2.6: waits for the target clock");
    }

    #[test]
    fn rmvf_clears_the_reset_flags() {
        let mut r = Rcc::default();
        r.write(CSR, 1 << 24, u32::MAX);
        assert_eq!(r.read(CSR) & 0xFF00_0000, 0);
    }
}
