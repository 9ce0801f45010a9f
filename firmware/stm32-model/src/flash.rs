//! The embedded flash interface's program/erase control (RM0383 §3.5, §3.8),
//! for sector erase: the unlock sequence, the lock, the parallelism, BSY,
//! and how long the erase stalls the CPU. Time is in nanoseconds, kept by
//! the caller's bus (`advance_ns`); a CPU access that must wait (a FLASH_CR
//! write while BSY, §3.5.1 note) moves time on to the end of the operation.
//!
//! Programming (PG, §3.5.4) is checked here ([`Flash::program`]: sequence,
//! alignment and parallelism errors, BSY for the word's programming time); the
//! bytes themselves are the caller's memory.
//!
//! Not modelled (a write that asks for it panics): mass erase, option bytes,
//! the interrupts, read/write protection, ×64 (needs VPP, §3.5.2 Table 6), and
//! sectors above 7 (the F411's 512 KiB, §3.3 Table 4).

use crate::unmodelled;

/// FLASH interface base (AHB1), RM0383 §2.3 Table 1, and its registers (§3.8.7
/// register map); the keys of FLASH_KEYR, §3.5.1.
pub use polyturn_regs::addr::{FLASH_CR as CR, FLASH_KEYR as KEYR, FLASH_R, FLASH_SR as SR};
pub use polyturn_regs::bits::flash_keyr::{KEY1, KEY2};
use polyturn_regs::bits::{flash_cr, flash_sr};
/// FLASH_SR bits, §3.8.4.
pub const SR_EOP: u32 = flash_sr::EOP.mask();
/// OPERR, WRPERR, PGAERR, PGPERR, PGSERR, RDERR
pub const SR_ERRORS: u32 = flash_sr::ERRORS;
pub const SR_BSY: u32 = flash_sr::BSY.mask();
pub const SR_PGSERR: u32 = flash_sr::PGSERR.mask();
pub const SR_PGPERR: u32 = flash_sr::PGPERR.mask();
pub const SR_PGAERR: u32 = flash_sr::PGAERR.mask();
/// Programming one word at ×32, DS10314 table "Flash memory programming"
/// t_prog: 16 µs typical, 100 µs max.
const PROG_NS: (u64, u64) = (16_000, 100_000);
/// FLASH_CR bits, §3.8.5.
pub const CR_PG: u32 = flash_cr::PG.mask();
pub const CR_SER: u32 = flash_cr::SER.mask();
pub const CR_MER: u32 = flash_cr::MER.mask();
pub const CR_SNB_SHIFT: u32 = flash_cr::SNB.shift;
pub const CR_SNB: u32 = flash_cr::SNB.mask();
pub const CR_PSIZE_SHIFT: u32 = flash_cr::PSIZE.shift;
pub const CR_PSIZE: u32 = flash_cr::PSIZE.mask();
pub const CR_STRT: u32 = flash_cr::STRT.mask();
pub const CR_EOPIE: u32 = flash_cr::EOPIE.mask();
pub const CR_LOCK: u32 = flash_cr::LOCK.mask();
/// FLASH_CR's reset value: locked (§3.8.5).
const CR_RESET: u32 = CR_LOCK;

/// Which of the datasheet's two figures an erase takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EraseTime {
    Typical,
    Max,
}

/// Sector erase time in ms, [×8, ×16, ×32] as (typical, max): DS10314
/// (STM32F411xC/E datasheet) table "Flash memory programming", t_ERASE16KB,
/// t_ERASE64KB, t_ERASE128KB.
fn erase_ms(sector_kib: u32, psize: u32) -> (u64, u64) {
    let t: [(u64, u64); 3] = match sector_kib {
        16 => [(400, 800), (300, 600), (250, 500)],
        64 => [(1200, 2400), (700, 1400), (550, 1100)],
        _ => [(2000, 4000), (1300, 2600), (1000, 2000)],
    };
    t[psize as usize]
}

/// Sector `n`'s size in KiB: 4 × 16, 1 × 64, 3 × 128 (§3.3 Table 4).
pub fn sector_kib(n: u32) -> u32 {
    match n {
        0..=3 => 16,
        4 => 64,
        _ => 128,
    }
}

/// One erase the interface performed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Erase {
    pub sector: u32,
    /// PSIZE as written: 0 = ×8, 1 = ×16, 2 = ×32 (§3.8.5)
    pub psize: u32,
    pub start_ns: u64,
    pub end_ns: u64,
}

#[derive(Clone, Debug)]
pub struct Flash {
    time: EraseTime,
    now_ns: u64,
    cr: u32,
    sr: u32,
    busy_until_ns: u64,
    /// 1 after KEY1 was written to a locked FLASH_CR
    key_stage: u8,
    /// a wrong key sequence locks FLASH_CR until reset (§3.5.1)
    locked_until_reset: bool,
    pub bus_errors: u32,
    pub erases: Vec<Erase>,
    /// words programmed
    pub programs: u64,
}

impl Flash {
    pub fn new(time: EraseTime) -> Flash {
        Flash {
            time,
            now_ns: 0,
            cr: CR_RESET,
            sr: 0,
            busy_until_ns: 0,
            key_stage: 0,
            locked_until_reset: false,
            bus_errors: 0,
            erases: Vec::new(),
            programs: 0,
        }
    }

    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// Time passes; an operation that ends clears BSY and STRT (§3.8.5
    /// STRT: "cleared when the BSY bit is cleared") and sets EOP if EOPIE.
    pub fn advance_ns(&mut self, ns: u64) {
        self.now_ns += ns;
        if self.sr & SR_BSY != 0 && self.now_ns >= self.busy_until_ns {
            self.sr &= !SR_BSY;
            self.cr &= !CR_STRT;
            if self.cr & CR_EOPIE != 0 {
                self.sr |= SR_EOP; // §3.8.4: set only if EOPIE = 1
            }
        }
    }

    pub fn read(&mut self, addr: u32) -> u32 {
        match addr {
            SR => self.sr,
            CR => self.cr,
            KEYR => 0,
            _ => unmodelled(&format!("FLASH read at {addr:#010x}")),
        }
    }

    pub fn write(&mut self, addr: u32, value: u32) {
        match addr {
            KEYR => self.write_keyr(value),
            // rc_w1: writing 1 clears (§3.8.4); BSY is read-only
            SR => self.sr &= !(value & (SR_EOP | SR_ERRORS)),
            CR => self.write_cr(value),
            _ => unmodelled(&format!("FLASH write at {addr:#010x}")),
        }
    }

    /// A CPU write of `size` bytes to flash address `addr`: whether it programs.
    /// §3.5.4: with PG set, unlocked and not BSY, a write of PSIZE's width at an
    /// address aligned to it programs (BSY for t_prog); a write without PG is a
    /// sequence error (PGSERR, §3.8.4 "a write access to the Flash memory is
    /// performed by the code while the control register has not been correctly
    /// configured"), one of another width a parallelism error (PGPERR), one not
    /// aligned an alignment error (PGAERR). Programming can only clear bits: the
    /// caller ANDs the value into its memory (an F4 without ECC; RM0383 gives no
    /// error for a word that was not erased).
    pub fn program(&mut self, addr: u32, size: u32) -> bool {
        if self.sr & SR_BSY != 0 {
            let wait = self.busy_until_ns - self.now_ns;
            self.advance_ns(wait); // §3.5.1: the access waits for BSY
        }
        let width = 1 << ((self.cr & CR_PSIZE) >> CR_PSIZE_SHIFT);
        let error = if self.locked() || self.cr & CR_PG == 0 {
            SR_PGSERR
        } else if size != width {
            SR_PGPERR
        } else if !addr.is_multiple_of(width) {
            SR_PGAERR
        } else {
            0
        };
        self.sr |= error;
        if error != 0 {
            return false;
        }
        let ns = if self.time == EraseTime::Typical { PROG_NS.0 } else { PROG_NS.1 };
        self.busy_until_ns = self.now_ns + ns;
        self.sr |= SR_BSY;
        self.programs += 1;
        true
    }

    /// When the operation under way ends, if one is (ns).
    pub fn busy_until_ns(&self) -> Option<u64> {
        (self.sr & SR_BSY != 0).then_some(self.busy_until_ns)
    }

    fn locked(&self) -> bool {
        self.cr & CR_LOCK != 0
    }

    /// §3.5.1: KEY1 then KEY2 unlocks FLASH_CR; "any wrong sequence will
    /// return a bus error and lock up the FLASH_CR register until the next
    /// reset". A key written while already unlocked is taken as a wrong
    /// sequence (the manual describes keys only for a locked register; the
    /// stricter reading).
    fn write_keyr(&mut self, value: u32) {
        let right = self.locked() && !self.locked_until_reset && (value == [KEY1, KEY2][self.key_stage as usize]);
        if !right {
            self.bus_errors += 1;
            self.locked_until_reset = true;
            self.cr |= CR_LOCK;
            self.key_stage = 0;
            return;
        }
        self.key_stage += 1;
        if self.key_stage == 2 {
            self.key_stage = 0;
            self.cr &= !CR_LOCK;
        }
    }

    fn write_cr(&mut self, value: u32) {
        // §3.5.1 note: a FLASH_CR write while BSY stalls the bus until BSY
        // clears
        if self.sr & SR_BSY != 0 {
            let wait = self.busy_until_ns - self.now_ns;
            self.advance_ns(wait);
        }
        if self.locked() {
            // §3.5.1: FLASH_CR is write-protected while locked. Setting LOCK
            // is what locks it; any other write is ignored.
            return;
        }
        if value & CR_MER != 0 || (value & CR_PSIZE) >> CR_PSIZE_SHIFT == 3 {
            unmodelled("FLASH_CR: mass erase or ×64");
        }
        let start = value & CR_STRT != 0 && self.cr & CR_STRT == 0;
        self.cr = value & (CR_PG | CR_SER | CR_SNB | CR_PSIZE | CR_STRT | CR_EOPIE | CR_LOCK);
        if start && value & CR_SER != 0 {
            self.start_erase();
        } else if start {
            self.cr &= !CR_STRT; // nothing selected: nothing starts
        }
    }

    /// §3.5.3 sector erase: SER, SNB, then STRT; BSY for the erase time at
    /// the parallelism PSIZE selects (§3.5.2, "the erase time depends on").
    fn start_erase(&mut self) {
        let sector = (self.cr & CR_SNB) >> CR_SNB_SHIFT;
        if sector > 7 {
            unmodelled("FLASH_CR.SNB above sector 7");
        }
        let psize = (self.cr & CR_PSIZE) >> CR_PSIZE_SHIFT;
        let (typ, max) = erase_ms(sector_kib(sector), psize);
        let ms = if self.time == EraseTime::Typical { typ } else { max };
        self.busy_until_ns = self.now_ns + ms * 1_000_000;
        self.sr |= SR_BSY;
        self.erases.push(Erase { sector, psize, start_ns: self.now_ns, end_ns: self.busy_until_ns });
    }
}

#[cfg(test)]
mod program_tests {
    use super::*;

    fn unlocked() -> Flash {
        let mut f = Flash::new(EraseTime::Typical);
        f.write(KEYR, KEY1);
        f.write(KEYR, KEY2);
        f
    }

    #[test]
    fn a_word_programs_only_with_pg_at_its_width_and_alignment() {
        let mut f = unlocked();
        assert!(!f.program(0x0804_0000, 4));
        assert_eq!(f.read(SR) & SR_PGSERR, SR_PGSERR, "no PG: sequence error");
        f.write(SR, SR_ERRORS);
        f.write(CR, CR_PG | 2 << CR_PSIZE_SHIFT);
        assert!(!f.program(0x0804_0000, 2));
        assert_eq!(f.read(SR) & SR_PGPERR, SR_PGPERR, "a halfword at ×32: parallelism error");
        f.write(SR, SR_ERRORS);
        assert!(!f.program(0x0804_0002, 4));
        assert_eq!(f.read(SR) & SR_PGAERR, SR_PGAERR);
        f.write(SR, SR_ERRORS);
        assert!(f.program(0x0804_0004, 4));
        assert_eq!(f.read(SR) & SR_BSY, SR_BSY);
        f.advance_ns(16_000);
        assert_eq!(f.read(SR) & SR_BSY, 0, "t_prog typical 16 µs");
        assert_eq!(f.programs, 1);
    }

    #[test]
    fn a_locked_interface_programs_nothing() {
        let mut f = Flash::new(EraseTime::Typical);
        f.write(CR, CR_PG | 2 << CR_PSIZE_SHIFT); // ignored: locked
        assert!(!f.program(0x0804_0000, 4));
        assert_eq!(f.programs, 0);
    }
}
