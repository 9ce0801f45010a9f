//! SYSCFG's memory remap (RM0383 §7.2.1) and EXTI routing (§7.2.3-§7.2.6),
//! and the EXTI controller (§10.3).

use super::RegFile;

pub const IMR: u32 = 0x00;
pub const EMR: u32 = 0x04;
pub const RTSR: u32 = 0x08;
pub const FTSR: u32 = 0x0C;
pub const SWIER: u32 = 0x10;
pub const PR: u32 = 0x14;

/// SYSCFG: registers as memory; EXTICR1..4 at 0x08..0x14 choose each line's port.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Syscfg {
    pub regs: RegFile,
}

/// What the CPU sees at address 0x0000_0000 (RM0383 §7.2.1, SYSCFG_MEMRMP
/// MEM_MODE, bits 1:0; §2.4 for the boot pins that set it at reset).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AtZero {
    /// 00: "Main Flash memory mapped at 0x0000 0000"
    Flash,
    /// 01: "System Flash memory mapped at 0x0000 0000"
    SystemMemory,
    /// 10: reserved on the F411
    Reserved,
    /// 11: "Embedded SRAM mapped at 0x0000 0000"
    Sram,
}

/// SYSCFG_MEMRMP's offset (§7.2.7, the register map).
pub const MEMRMP: u32 = 0x00;

impl Syscfg {
    /// The memory at 0 by MEMRMP.MEM_MODE (§7.2.1).
    pub fn at_zero(&self) -> AtZero {
        match self.regs.get(MEMRMP) & 0b11 {
            0b00 => AtZero::Flash,
            0b01 => AtZero::SystemMemory,
            0b10 => AtZero::Reserved,
            _ => AtZero::Sram,
        }
    }

    /// The port (0 = A, 1 = B, ...) routed to EXTI line `line`: EXTIx[3:0] of
    /// SYSCFG_EXTICR1..4 (§7.2.3-§7.2.6).
    pub fn port_of_line(&self, line: u8) -> u32 {
        self.regs.field(0x08 + 4 * (line as u32 / 4), 4 * (line as u32 % 4), 4)
    }
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Exti {
    regs: RegFile,
}

impl Exti {
    /// An edge on pin `pin` of port `port` (0 = A): sets PR's bit when SYSCFG routes
    /// the port to that line and the edge's trigger is selected (§10.2.3, §10.3.3,
    /// §10.3.4). Returns whether it did.
    pub fn edge(&mut self, syscfg: &Syscfg, port: u32, pin: u8, rising: bool) -> bool {
        let trig = if rising { RTSR } else { FTSR };
        let hit = syscfg.port_of_line(pin) == port && self.regs.get(trig) >> pin & 1 == 1;
        if hit {
            self.regs.set(PR, self.regs.get(PR) | 1 << pin);
        }
        hit
    }

    pub fn read(&self, off: u32) -> u32 {
        self.regs.get(off)
    }

    pub fn write(&mut self, off: u32, value: u32, mask: u32) {
        let v = value & mask;
        match off {
            PR => self.regs.set(PR, self.regs.get(PR) & !v), // §10.3.6: rc_w1
            // §10.3.5: writing 1 to SWIERx sets PRx when the line is unmasked
            SWIER => self.regs.set(PR, self.regs.get(PR) | v & self.regs.get(IMR)),
            _ => self.regs.write(off, value, mask),
        }
    }

    /// The level EXTI drives into the NVIC for lines `lo..=hi`: PR & IMR (§10.2.2
    /// figure 30; lines 5-9 and 10-15 share a vector, §10.1.3 table 37).
    pub fn pending(&self, lo: u8, hi: u8) -> bool {
        let bits = self.regs.get(PR) & self.regs.get(IMR);
        bits >> lo & ((1u32 << (hi - lo + 1)) - 1) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_mode_chooses_what_is_at_zero() {
        let mut sys = Syscfg::default();
        assert_eq!(sys.at_zero(), AtZero::Flash, "MEM_MODE resets to the boot pins' choice; BOOT0 = 0: flash");
        for (mode, at) in [(0b01, AtZero::SystemMemory), (0b11, AtZero::Sram), (0b00, AtZero::Flash)] {
            sys.regs.write(MEMRMP, mode, 0b11);
            assert_eq!(sys.at_zero(), at, "MEM_MODE {mode:02b} (§7.2.1)");
        }
    }

    #[test]
    fn an_edge_pends_only_on_its_routed_port_and_selected_trigger() {
        let mut sys = Syscfg::default();
        sys.regs.set(0x14, 1 << 8); // EXTICR4: line 14 from port B
        let mut e = Exti::default();
        e.write(RTSR, 1 << 14, u32::MAX);
        e.write(IMR, 1 << 14, u32::MAX);
        assert!(!e.edge(&sys, 0, 14, true), "port A is not routed");
        assert!(!e.edge(&sys, 1, 14, false), "falling edge not selected");
        assert!(e.edge(&sys, 1, 14, true));
        assert!(e.pending(10, 15) && !e.pending(5, 9));
        e.write(PR, 1 << 14, u32::MAX);
        assert!(!e.pending(10, 15), "§10.3.6: writing 1 clears");
    }

    #[test]
    fn swier_pends_only_an_unmasked_line() {
        let mut e = Exti::default();
        e.write(SWIER, 1 << 3, u32::MAX);
        assert_eq!(e.read(PR), 0);
        e.write(IMR, 1 << 3, u32::MAX);
        e.write(SWIER, 1 << 3, u32::MAX);
        assert_eq!(e.read(PR), 1 << 3);
    }
}
