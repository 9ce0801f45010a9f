//! A GPIO port (RM0383 §8). Reset values from §8.4.1 (MODER: 0xA800_0000 port A,
//! 0x0000_0280 port B), §8.4.3 (OSPEEDR) and §8.4.4 (PUPDR). The outside world drives an input pin with
//! [`Port::drive`]; `None` leaves it floating, where the configured pull decides its
//! level (§8.3.1 table 24: pull-up reads 1, pull-down 0; a floating pin with no pull
//! reads 0 here, which silicon does not promise). Edges on a pin's input level are
//! returned so the caller can pass them to EXTI (§10.2.3).

use super::RegFile;

/// Register offsets (§8.4.11 register map).
pub use polyturn_regs::addr::gpio_off::{AFRH, AFRL, BSRR, IDR, LCKR, MODER, ODR, OSPEEDR, OTYPER, PUPDR};

/// MODER values (§8.4.1).
pub const INPUT: u32 = 0;
pub const OUTPUT: u32 = 1;
pub const ALTERNATE: u32 = 2;

/// An edge on a pin's input level: (pin, rising).
pub type PinEdge = (u8, bool);

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Port {
    regs: RegFile,
    ext: [Option<bool>; 16],
    last: u16,
    /// Cycle at which each pin first became an output (for the boot check).
    pub output_since: [Option<u64>; 16],
}

impl Port {
    /// Reset values from the §8.4.11 register map: port A has the SWD pins
    /// (PA13/PA14/PA15) in AF with pulls, port B PB3/PB4 (JTAG) likewise.
    pub fn new(port: char) -> Port {
        let resets: &[(u32, u32)] = match port {
            'A' => &[(MODER, 0xA800_0000), (OSPEEDR, 0x0C00_0000), (PUPDR, 0x6400_0000)],
            'B' => &[(MODER, 0x0000_0280), (OSPEEDR, 0x0000_00C0), (PUPDR, 0x0000_0100)],
            _ => &[],
        };
        let mut p = Port { regs: RegFile::new(resets), ext: [None; 16], last: 0, output_since: [None; 16] };
        p.last = p.levels();
        p
    }

    /// Two-bit field of pin `pin` in a MODER/OSPEEDR/PUPDR-shaped register.
    pub fn field(&self, off: u32, pin: u8) -> u32 {
        self.regs.field(off, 2 * pin as u32, 2)
    }

    /// The alternate function selected for `pin` (AFRL/AFRH, §8.4.9/§8.4.10).
    pub fn afr(&self, pin: u8) -> u32 {
        let off = if pin < 8 { AFRL } else { AFRH };
        self.regs.field(off, 4 * (pin as u32 % 8), 4)
    }

    /// The input level of `pin` (§8.3.9-§8.3.12): an output's input buffer sees
    /// ODR; otherwise what is driven from outside, else the pull.
    pub fn level(&self, pin: u8) -> bool {
        if self.field(MODER, pin) == OUTPUT {
            return self.regs.get(ODR) >> pin & 1 == 1;
        }
        self.ext[pin as usize].unwrap_or(self.field(PUPDR, pin) == 1)
    }

    fn levels(&self) -> u16 {
        (0..16).fold(0, |v, p| v | (self.level(p) as u16) << p)
    }

    /// What `pin` shows outside when software drives it (output mode): ODR;
    /// `None` for an input or an alternate function (ask the peripheral).
    pub fn pin_out(&self, pin: u8) -> Option<bool> {
        (self.field(MODER, pin) == OUTPUT).then(|| self.regs.get(ODR) >> pin & 1 == 1)
    }

    pub fn read(&self, off: u32) -> u32 {
        match off {
            IDR => self.levels() as u32, // §8.4.5, read-only
            BSRR => 0,                   // §8.4.7: write-only
            _ => self.regs.get(off),
        }
    }

    /// A write of the bits in `mask`, at CPU cycle `now`.
    pub fn write(&mut self, off: u32, value: u32, mask: u32, now: u64) -> Vec<PinEdge> {
        let value = value & mask;
        match off {
            IDR => {}
            // §8.4.7: BSy sets ODRy, BRy resets it; "if both BSx and BRx are set, BSx has priority"
            BSRR => {
                let odr = self.regs.get(ODR) & !(value >> 16) | value & 0xFFFF;
                self.regs.set(ODR, odr);
            }
            _ => {
                self.regs.write(off, value, mask);
                if off == ODR {
                    self.regs.set(ODR, self.regs.get(ODR) & 0xFFFF); // §8.4.6: bits 31:16 reserved
                }
                if off == MODER {
                    for p in 0..16u8 {
                        if self.field(MODER, p) == OUTPUT && self.output_since[p as usize].is_none() {
                            self.output_since[p as usize] = Some(now);
                        }
                    }
                }
            }
        }
        self.edges()
    }

    /// What the outside world drives on `pin` (`None`: nothing, floating).
    pub fn external(&self, pin: u8) -> Option<bool> {
        self.ext[pin as usize]
    }

    /// The outside world drives `pin` to `level` (`None`: floating).
    pub fn drive(&mut self, pin: u8, level: Option<bool>) -> Vec<PinEdge> {
        self.ext[pin as usize] = level;
        self.edges()
    }

    fn edges(&mut self) -> Vec<PinEdge> {
        let now = self.levels();
        let changed = now ^ self.last;
        self.last = now;
        (0..16u8).filter(|p| changed >> p & 1 == 1).map(|p| (p, now >> p & 1 == 1)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bsrr_set_wins_over_reset_and_reads_zero() {
        let mut p = Port::new('C');
        p.write(MODER, OUTPUT << 26, u32::MAX, 5);
        p.write(BSRR, 1 << 13 | 1 << 29, u32::MAX, 6);
        assert_eq!(p.read(ODR), 1 << 13, "§8.4.7: BS has priority");
        assert_eq!(p.read(BSRR), 0);
        p.write(BSRR, 1 << 29, u32::MAX, 7);
        assert_eq!(p.read(ODR), 0);
        assert_eq!(p.output_since[13], Some(5));
    }

    #[test]
    fn a_floating_input_reads_its_pull_and_a_driven_one_its_level() {
        let mut p = Port::new('B');
        p.write(PUPDR, 1 << 28, u32::MAX, 0); // PB14 pull-up
        assert!(p.level(14));
        assert_eq!(p.drive(14, Some(false)), vec![(14, false)]);
        assert_eq!(p.read(IDR) >> 14 & 1, 0);
        assert_eq!(p.drive(14, None), vec![(14, true)], "released, the pull-up takes it high");
    }

    #[test]
    fn reset_values_put_the_debug_pins_in_alternate_function() {
        let a = Port::new('A');
        assert_eq!(a.field(MODER, 13), ALTERNATE);
        assert_eq!(a.field(MODER, 14), ALTERNATE);
        assert_eq!(a.field(PUPDR, 13), 1, "PA13 SWDIO pull-up");
        assert_eq!(a.afr(9), 0);
    }
}
