//! The Cortex-M4's private peripheral bus registers the firmware uses (PM0214 §4):
//! the NVIC (§4.3), the SCB (§4.4), SysTick's registers (§4.5; the firmware does not
//! run it), DWT CYCCNT and DCB DEMCR (ARMv7-M ARM C1.8, C1.6). Offsets are from
//! 0xE000_0000. Exception entry and return are the CPU's, in the emulator.

use super::RegFile;

pub const ISER: u32 = 0xE100;
pub const ICER: u32 = 0xE180;
pub const ISPR: u32 = 0xE200;
pub const ICPR: u32 = 0xE280;
pub const IABR: u32 = 0xE300;
pub const IPR: u32 = 0xE400;
pub const ICSR: u32 = 0xED04;
pub const VTOR: u32 = 0xED08;
pub const AIRCR: u32 = 0xED0C;
pub const SHPR1: u32 = 0xED18;
pub const STIR: u32 = 0xEF00;
pub const DWT_CTRL: u32 = 0x1000;
pub const DWT_CYCCNT: u32 = 0x1004;
pub const DEMCR: u32 = 0xEDFC;
/// DHCSR (C1.6.2): reads 0, no debugger attached (C_DEBUGEN clear), as on a
/// board in use; writes are the debugger's (DBGKEY) and are not modelled.
pub const DHCSR: u32 = 0xEDF0;
/// The F411's vector table has 16 + 86 entries (RM0383 §10.1.3 table 37).
pub const NIRQ: usize = 86;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Nvic {
    regs: RegFile,
    pub enabled: [bool; NIRQ],
    /// pending exception numbers (16 + IRQ, or 14 PendSV / 15 SysTick)
    pub pending: [bool; 16 + NIRQ],
    /// priority bytes by exception number (only bits 7:4 implemented, §4.3.7)
    pub prio: [u8; 16 + NIRQ],
    cyc_base: u32,
    cyc_at: u64,
    /// AIRCR.SYSRESETREQ was written with its key
    pub reset_requested: bool,
    /// the MPU's registers, in the same system space (`mpu`)
    pub mpu: super::mpu::Mpu,
}

impl Default for Nvic {
    /// CPUID r0p1 Cortex-M4 (§4.4.1), AIRCR's VECTKEYSTAT, CCR.STKALIGN (§4.4.7),
    /// FPCCR ASPEN|LSPEN, ICTR 2 (up to 96 IRQs), DWT_CTRL NUMCOMP = 4.
    fn default() -> Nvic {
        let resets = [
            (0xED00, 0x410F_C241),
            (AIRCR, 0xFA05_0000),
            (0xED14, 0x200),
            (0xEF34, 0xC000_0000),
            (0xE004, 2),
            (DWT_CTRL, 0x4000_0000),
        ];
        Nvic {
            regs: RegFile::new(&resets),
            enabled: [false; NIRQ],
            pending: [false; 16 + NIRQ],
            prio: [0; 16 + NIRQ],
            cyc_base: 0,
            cyc_at: 0,
            reset_requested: false,
            mpu: super::mpu::Mpu::default(),
        }
    }
}

impl Nvic {
    /// The group (pre-emption) part of priority byte `p` under AIRCR.PRIGROUP (§4.4.5).
    pub fn group(&self, p: u8) -> u32 {
        let g = self.regs.get(AIRCR) >> 8 & 7;
        p as u32 & !((2u32 << g) - 1) & 0xFF
    }

    pub fn vtor(&self) -> u32 {
        self.regs.get(VTOR)
    }

    fn cycles_on(&self) -> bool {
        self.regs.get(DEMCR) >> 24 & 1 == 1 && self.regs.get(DWT_CTRL) & 1 == 1
    }

    fn cyccnt(&self, now: u64) -> u32 {
        if !self.cycles_on() {
            return self.cyc_base;
        }
        self.cyc_base.wrapping_add((now - self.cyc_at) as u32)
    }

    /// The highest-priority pending exception (ties to the lowest number, §4.3.9 note).
    pub fn best_pending(&self) -> Option<usize> {
        (0..16 + NIRQ)
            .filter(|&e| self.pending[e] && (e < 16 || self.enabled[e - 16]))
            .min_by_key(|&e| (self.prio[e], e))
    }

    fn bits(&self, woff: u32, test: impl Fn(usize) -> bool) -> u32 {
        (0..32)
            .filter(|i| ((32 * (woff / 4) + i) as usize) < NIRQ && test((32 * (woff / 4) + i) as usize))
            .fold(0, |v, i| v | 1 << i)
    }

    /// A read at CPU cycle `now`, with `active` the exceptions being handled and
    /// `ipsr` the current one (for ICSR.VECTACTIVE).
    pub fn read(&self, off: u32, now: u64, active: &[usize], ipsr: u32) -> u32 {
        let in_bank = |base: u32| (base..base + 12).contains(&off);
        match off {
            _ if in_bank(ISER) => self.bits(off - ISER, |n| self.enabled[n]),
            _ if in_bank(ICER) => self.bits(off - ICER, |n| self.enabled[n]),
            _ if in_bank(ISPR) => self.bits(off - ISPR, |n| self.pending[16 + n]),
            _ if in_bank(ICPR) => self.bits(off - ICPR, |n| self.pending[16 + n]),
            _ if in_bank(IABR) => self.bits(off - IABR, |n| active.contains(&(16 + n))),
            _ if (IPR..IPR + NIRQ as u32).contains(&off) => (0..4)
                .filter(|i| ((off - IPR + i) as usize) < NIRQ)
                .fold(0, |v, i| v | (self.prio[16 + (off - IPR + i) as usize] as u32) << (8 * i)),
            _ if (SHPR1..SHPR1 + 12).contains(&off) => {
                (0..4).fold(0, |v, i| v | (self.prio[(4 + off - SHPR1 + i) as usize] as u32) << (8 * i))
            }
            // §4.4.3: VECTACTIVE, VECTPENDING, ISRPENDING, PENDSVSET, PENDSTSET
            ICSR => {
                let pend = self.best_pending().unwrap_or(0) as u32;
                // ISRPENDING: an external interrupt is pending (not PendSV/SysTick)
                let any = self.pending[16..].iter().any(|&p| p) as u32;
                ipsr | pend << 12 | any << 22 | (self.pending[14] as u32) << 28 | (self.pending[15] as u32) << 26
            }
            DWT_CYCCNT => self.cyccnt(now),
            _ if super::mpu::Mpu::claims(off) => self.mpu.read(off),
            _ => self.regs.get(off),
        }
    }

    /// A write of the bits in `mask` at CPU cycle `now`.
    pub fn write(&mut self, off: u32, value: u32, mask: u32, now: u64) {
        let v = value & mask;
        for (base, act) in [(ISER, 0), (ICER, 1), (ISPR, 2), (ICPR, 3)] {
            if (base..base + 12).contains(&off) {
                for n in (0..32)
                    .filter(|i| v >> i & 1 == 1)
                    .map(|i| (32 * ((off - base) / 4) + i) as usize)
                    .filter(|&n| n < NIRQ)
                {
                    match act {
                        0 => self.enabled[n] = true,
                        1 => self.enabled[n] = false,
                        2 => self.pending[16 + n] = true,
                        _ => self.pending[16 + n] = false,
                    }
                }
                return;
            }
        }
        if super::mpu::Mpu::claims(off) {
            // (word accesses only, as the firmware makes them)
            self.mpu.write(off, v);
            return;
        }
        match off {
            _ if (IPR..IPR + NIRQ as u32).contains(&off) => {
                self.set_prio(16 + (off - IPR) as usize, v, mask, 16 + NIRQ)
            }
            _ if (SHPR1..SHPR1 + 12).contains(&off) => self.set_prio(4 + (off - SHPR1) as usize, v, mask, 16),
            // §4.3.8: INTID names an interrupt; one the part lacks is ignored
            STIR if ((v & 0x1FF) as usize) < NIRQ => self.pending[16 + (v & 0x1FF) as usize] = true,
            STIR => {}
            ICSR => self.write_icsr(v),
            // §4.4.5: writes without VECTKEY 0x05FA are ignored
            AIRCR if v >> 16 == 0x05FA => {
                self.reset_requested |= v & 4 != 0;
                self.regs.set(AIRCR, 0xFA05_0000 | v & 0x700);
            }
            AIRCR => {}
            DWT_CYCCNT => (self.cyc_base, self.cyc_at) = (v, now),
            DWT_CTRL | DEMCR => {
                let cur = self.cyccnt(now);
                self.regs.write(off, value, mask);
                (self.cyc_base, self.cyc_at) = (cur, now);
            }
            _ => self.regs.write(off, value, mask),
        }
    }

    /// §4.3.7: "each priority field holds a priority value, 0-255 ... [the F4]
    /// implements only bits[7:4]".
    fn set_prio(&mut self, first: usize, v: u32, mask: u32, end: usize) {
        for i in 0..4 {
            if mask >> (8 * i) & 0xFF != 0 && first + i < end {
                self.prio[first + i] = (v >> (8 * i)) as u8 & 0xF0;
            }
        }
    }

    /// §4.4.3: PENDSVSET/PENDSVCLR (bits 28/27), PENDSTSET/PENDSTCLR (26/25).
    fn write_icsr(&mut self, v: u32) {
        for (bit, exc, set) in [(28, 14, true), (27, 14, false), (26, 15, true), (25, 15, false)] {
            if v >> bit & 1 == 1 {
                self.pending[exc] = set;
            }
        }
    }

    /// SysTick's CTRL.ENABLE (§4.5.1): the firmware never starts it.
    pub fn systick_on(&self) -> bool {
        self.regs.get(0xE010) & 1 == 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn priorities_keep_their_top_four_bits_and_prigroup_splits_them() {
        let mut n = Nvic::default();
        n.write(IPR + 24, 0x5F << 8, 0xFF00, 0); // IRQ 25's byte
        assert_eq!(n.prio[16 + 25], 0x50);
        assert_eq!(n.read(IPR + 24, 0, &[], 0), 0x50 << 8);
        n.write(AIRCR, 0x05FA_0000 | 5 << 8, u32::MAX, 0);
        assert_eq!(n.group(0x50), 0x40, "PRIGROUP 5: bits 7:6 pre-empt");
        n.write(AIRCR, 4, u32::MAX, 0);
        assert!(!n.reset_requested, "no VECTKEY, ignored");
        n.write(AIRCR, 0x05FA_0004, u32::MAX, 0);
        assert!(n.reset_requested);
    }

    #[test]
    fn set_enable_and_pending_pick_the_lowest_priority_value_first() {
        let mut n = Nvic::default();
        n.write(ISER, 1 << 3 | 1 << 7, u32::MAX, 0);
        n.write(ISPR, 1 << 3 | 1 << 7, u32::MAX, 0);
        n.write(IPR + 4, 0x20 << 24, u32::MAX, 0); // IRQ 7 at 0x20, IRQ 3 at 0
        assert_eq!(n.best_pending(), Some(16 + 3));
        n.write(IPR, 0x30 << 24, u32::MAX, 0);
        assert_eq!(n.best_pending(), Some(16 + 7));
        n.write(ICER, 1 << 7, u32::MAX, 0);
        assert_eq!(n.best_pending(), Some(16 + 3), "a disabled IRQ is not taken");
    }

    #[test]
    fn no_debugger_is_attached_c1_6_2() {
        assert_eq!(Nvic::default().read(DHCSR, 0, &[], 0) & 1, 0, "C_DEBUGEN clear");
    }

    #[test]
    fn cyccnt_counts_only_while_trcena_and_cyccntena() {
        let mut n = Nvic::default();
        n.write(DWT_CTRL, 0x4000_0001, u32::MAX, 10);
        assert_eq!(n.read(DWT_CYCCNT, 50, &[], 0), 0);
        n.write(DEMCR, 1 << 24, u32::MAX, 100);
        assert_eq!(n.read(DWT_CYCCNT, 150, &[], 0), 50);
    }
}
