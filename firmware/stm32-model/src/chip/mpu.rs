//! The Cortex-M4's memory protection unit, as far as the firmware programs
//! it: which accesses a privileged thread or handler may make at an address
//! (Cortex-M4 Devices Generic User Guide, ARM DUI 0553A §4.5; ST's PM0214
//! gives the same registers). Offsets are from 0xE000_0000, as the NVIC's.
//! Memory attributes (TEX, C, B, S) are kept but not modelled: the F411 has
//! no cache behind the core for them to act on.

/// MPU_TYPER (§4.5.1): DREGION = 8 data regions, no separate instruction
/// regions.
pub const TYPE: u32 = 0xED90;
/// MPU_CTRL (§4.5.2): ENABLE, HFNMIENA, PRIVDEFENA.
pub const CTRL: u32 = 0xED94;
/// MPU_RNR (§4.5.3): the region RBAR and RASR access.
pub const RNR: u32 = 0xED98;
/// MPU_RBAR (§4.5.4): ADDR, VALID, REGION.
pub const RBAR: u32 = 0xED9C;
/// MPU_RASR (§4.5.5): XN, AP, TEX/S/C/B, SRD, SIZE, ENABLE.
pub const RASR: u32 = 0xEDA0;

pub const CTRL_ENABLE: u32 = 1 << 0;
pub const CTRL_PRIVDEFENA: u32 = 1 << 2;
pub const RBAR_VALID: u32 = 1 << 4;
pub const RASR_ENABLE: u32 = 1;
pub const RASR_XN: u32 = 1 << 28;
/// AP = 0b110: read-only, privileged and unprivileged (Table 4-47).
pub const AP_READ_ONLY: u32 = 0b110 << 24;
/// AP = 0b011: full access (Table 4-47).
pub const AP_FULL: u32 = 0b011 << 24;

/// Regions the F411's MPU has (MPU_TYPER.DREGION, §4.5.1).
pub const REGIONS: usize = 8;

/// What a privileged access may do at an address.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Access {
    pub read: bool,
    pub write: bool,
    pub fetch: bool,
}

const ALL: Access = Access { read: true, write: true, fetch: true };
const NONE: Access = Access { read: false, write: false, fetch: false };

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Mpu {
    ctrl: u32,
    rnr: u32,
    rbar: [u32; REGIONS],
    rasr: [u32; REGIONS],
}

impl Mpu {
    /// Whether `off` is one of the MPU's registers (the alias registers at
    /// 0xEDA4..0xEDB8 are not: the firmware does not use them).
    pub fn claims(off: u32) -> bool {
        (TYPE..=RASR).contains(&off)
    }

    pub fn read(&self, off: u32) -> u32 {
        let r = (self.rnr as usize) % REGIONS;
        match off {
            TYPE => (REGIONS as u32) << 8,
            CTRL => self.ctrl,
            RNR => self.rnr,
            // §4.5.4: VALID reads 0, REGION the region RNR names
            RBAR => self.rbar[r] | r as u32,
            RASR => self.rasr[r],
            _ => 0,
        }
    }

    pub fn write(&mut self, off: u32, v: u32) {
        match off {
            CTRL => self.ctrl = v & 0b111,
            RNR => self.rnr = v & 0xFF,
            RBAR => {
                // §4.5.4: with VALID, REGION selects the region (and is
                // written to RNR); without it, RNR's region is updated
                if v & RBAR_VALID != 0 {
                    self.rnr = v & 0xF;
                }
                self.rbar[(self.rnr as usize) % REGIONS] = v & !0x1F;
            }
            RASR => self.rasr[(self.rnr as usize) % REGIONS] = v,
            _ => {}
        }
    }

    /// A privileged access at `addr` (the firmware runs privileged, in
    /// thread and handler mode alike; HardFault and NMI are not modelled
    /// here: with HFNMIENA clear the MPU is off for them, §4.5.2).
    pub fn access(&self, addr: u32) -> Access {
        if self.ctrl & CTRL_ENABLE == 0 {
            return ALL;
        }
        // §4.5: where regions overlap, the highest-numbered one's attributes
        match (0..REGIONS).rev().find(|&r| self.covers(r, addr)) {
            Some(r) => permissions(self.rasr[r]),
            // PRIVDEFENA: the default memory map as a background region for
            // privileged accesses; without it, a fault
            None if self.ctrl & CTRL_PRIVDEFENA != 0 => ALL,
            None => NONE,
        }
    }

    /// Region `r` is enabled and `addr` lies in it, outside any disabled
    /// subregion (§4.5.5: SIZE gives 2^(SIZE+1) bytes; §4.5.4: the base is
    /// aligned to the size; subregions are eighths of regions of 256 bytes
    /// and more).
    fn covers(&self, r: usize, addr: u32) -> bool {
        let rasr = self.rasr[r];
        if rasr & RASR_ENABLE == 0 {
            return false;
        }
        let size = 2u64 << ((rasr >> 1) & 0x1F);
        let base = u64::from(self.rbar[r]) & !(size - 1);
        let a = u64::from(addr);
        if !(base..base + size).contains(&a) {
            return false;
        }
        let srd = (rasr >> 8) & 0xFF;
        size < 256 || srd >> ((a - base) / (size / 8)) & 1 == 0
    }
}

/// A region's privileged permissions from its AP field (Table 4-47) and XN.
fn permissions(rasr: u32) -> Access {
    let (read, write) = match (rasr >> 24) & 0b111 {
        0b001..=0b011 => (true, true),
        0b101..=0b111 => (true, false),
        // 000: no access; 100: reserved
        _ => (false, false),
    };
    Access { read, write, fetch: read && rasr & RASR_XN == 0 }
}

impl Mpu {
    /// Region `r`'s memory type is Normal, from its TEX, C and B (Table
    /// 4-45): not Strongly-ordered (TEX 000, C 0, B 0) nor Device (TEX
    /// 000 with B alone, or TEX 010 with neither). Instructions are fetched
    /// from Normal memory.
    pub fn normal(&self, r: usize) -> bool {
        let rasr = self.rasr[r % REGIONS];
        let (tex, c, b) = ((rasr >> 19) & 0b111, (rasr >> 17) & 1, (rasr >> 16) & 1);
        !matches!((tex, c, b), (0b000, 0, _) | (0b010, 0, 0))
    }

    /// Whether region `r` is enabled.
    pub fn enabled(&self, r: usize) -> bool {
        self.rasr[r % REGIONS] & RASR_ENABLE != 0
    }
}

/// RASR's SIZE field for a region of `bytes` (a power of two, 32 or more):
/// 2^(SIZE+1) = bytes (§4.5.5).
pub const fn size_field(bytes: u32) -> u32 {
    (bytes.trailing_zeros() - 1) << 1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn region(m: &mut Mpu, n: u32, base: u32, rasr: u32) {
        m.write(RBAR, base | RBAR_VALID | n);
        m.write(RASR, rasr);
    }

    #[test]
    fn off_it_allows_everything_and_names_eight_regions() {
        let m = Mpu::default();
        assert_eq!(m.access(0x2000_0000), ALL);
        assert_eq!(m.read(TYPE), 8 << 8, "DREGION = 8");
    }

    #[test]
    fn a_read_only_region_refuses_writes_and_the_background_allows_the_rest() {
        let mut m = Mpu::default();
        region(&mut m, 0, 0x2000_0000, AP_READ_ONLY | size_field(32 * 1024) | RASR_ENABLE);
        m.write(CTRL, CTRL_ENABLE | CTRL_PRIVDEFENA);
        assert_eq!(m.access(0x2000_7FFC), Access { read: true, write: false, fetch: true });
        assert_eq!(m.access(0x2000_8000), ALL, "past the 32 KiB: the default map");
        m.write(CTRL, CTRL_ENABLE);
        assert_eq!(m.access(0x2000_8000), NONE, "without PRIVDEFENA no background");
    }

    #[test]
    fn the_highest_region_wins_and_a_disabled_subregion_falls_through() {
        let mut m = Mpu::default();
        region(&mut m, 0, 0x2000_0000, AP_READ_ONLY | size_field(64 * 1024) | RASR_ENABLE);
        // region 1: full access over the top eighth (8 KiB) only
        let srd = 0x7F << 8;
        region(&mut m, 1, 0x2000_0000, AP_FULL | RASR_XN | srd | size_field(64 * 1024) | RASR_ENABLE);
        m.write(CTRL, CTRL_ENABLE | CTRL_PRIVDEFENA);
        assert_eq!(m.access(0x2000_E000), Access { read: true, write: true, fetch: false });
        assert!(!m.access(0x2000_DFFC).write, "below it region 0's read-only");
    }

    #[test]
    fn rbar_without_valid_updates_the_region_rnr_names() {
        let mut m = Mpu::default();
        m.write(RNR, 3);
        m.write(RBAR, 0x2000_4000);
        assert_eq!(m.read(RBAR), 0x2000_4003, "ADDR, and REGION = 3");
        m.write(RBAR, RBAR_VALID | 5);
        assert_eq!(m.read(RNR), 5, "VALID writes REGION to RNR");
    }

    #[test]
    fn size_fields_give_their_powers_of_two() {
        assert_eq!(size_field(32), 4 << 1, "the smallest region, SIZE = 4");
        assert_eq!(size_field(32 * 1024), 14 << 1);
        assert_eq!(size_field(16 * 1024), 13 << 1);
    }
}
