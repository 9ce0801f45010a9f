//! The settings' sector erase as a register program (RM0383 §3.5.3), at ×32
//! parallelism. embassy-stm32 0.6's F4 erase never sets PSIZE
//! (`flash/f4.rs`, `blocking_erase_sector`), so it erases at FLASH_CR's
//! reset value, ×8: a 128 KiB sector then takes 2 s typical, 4 s at most,
//! against 1 s and 2 s at ×32 (DS10314, "Flash memory programming",
//! t_ERASE128KB). ×32 needs VDD 2.7 to 3.6 V (§3.5.2 Table 6): the Black
//! Pill's 3.3 V regulator. The host runs this program through the model of
//! the flash interface (`polyturn_stm32_model::flash`, tests/flash_erase.rs).

use crate::board::SYSCLK_HZ;
use crate::regs::Op;
use polyturn_regs::bits::{flash_cr, flash_sr};

/// FLASH interface registers (RM0383 §2.3 Table 1, §3.8.7 register map).
pub use polyturn_regs::addr::{FLASH_CR as CR, FLASH_KEYR as KEYR, FLASH_R, FLASH_SR as SR};
/// The unlock keys (§3.5.1).
pub use polyturn_regs::bits::flash_keyr::{KEY1, KEY2};
/// FLASH_SR (§3.8.4): EOP, the error flags (OPERR, WRPERR, PGAERR, PGPERR,
/// PGSERR, RDERR), BSY.
pub const SR_EOP: u32 = flash_sr::EOP.mask();
pub const SR_ERRORS: u32 = flash_sr::ERRORS;
pub const SR_BSY: u32 = flash_sr::BSY.mask();
/// FLASH_CR (§3.8.5).
pub const CR_SER: u32 = flash_cr::SER.mask();
pub const CR_SNB_SHIFT: u32 = flash_cr::SNB.shift;
pub const CR_PSIZE_X32: u32 = flash_cr::PSIZE.val(flash_cr::PSIZE_X32);
pub const CR_STRT: u32 = flash_cr::STRT.mask();
pub const CR_LOCK: u32 = flash_cr::LOCK.mask();

/// The sectors a program may erase: the settings' two (§3.3 Table 4;
/// `memory.x` keeps the code in sectors 0 to 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SettingsSector {
    Six = 6,
    Seven = 7,
}

impl SettingsSector {
    /// Offset from the start of flash: sectors 5 to 7 are 128 KiB each
    /// from 0x0802_0000 (§3.3 Table 4).
    pub const fn offset(self) -> u32 {
        0x2_0000 * (self as u32 - 4)
    }
}

/// The longest a 128 KiB sector erase takes at ×32 (DS10314, max).
pub const ERASE_MAX_US: u32 = 2_000_000;
/// The longest one 32-bit word takes to program (DS10314, t_prog max).
pub const WORD_PROGRAM_MAX_US: u32 = 100;

/// BSY is polled at most this many times. A poll is at least a load, a
/// test and a branch (≥ 4 cycles; 7 in the built loop), so the wait gives
/// up no sooner than twice the longest erase; the watchdog (`iwdg`, 5.4 s
/// at the shortest) may end a flash that never finishes first.
const POLLS: u32 = 2 * ERASE_MAX_US / 4 * (SYSCLK_HZ / 1_000_000);

/// Locks FLASH_CR: after a program that stopped early (a write while BSY
/// waits for the operation to end, §3.5.1 note, so this aborts nothing).
pub const LOCK: [Op; 1] = [Op::Write(CR, CR_LOCK)];

/// Erases `sector` at ×32 and locks FLASH_CR again. `Err` from
/// `regs::apply` names the step that failed: a BSY wait (index 3 or 7) or
/// the final error check (index 9); then apply `LOCK`.
pub fn erase_sector(sector: SettingsSector) -> [Op; 10] {
    // the sector's number in SNB, as constants (a field's `val` checks its
    // width at compile time; nothing here can panic at run time)
    const SNB_6: u32 = flash_cr::SNB.val(6);
    const SNB_7: u32 = flash_cr::SNB.val(7);
    let snb = match sector {
        SettingsSector::Six => SNB_6,
        SettingsSector::Seven => SNB_7,
    };
    let cr = CR_PSIZE_X32 | CR_SER | snb;
    [
        // Locked first: keys written to an unlocked FLASH_CR are a wrong
        // sequence, a bus error that locks it until reset (§3.5.1); setting
        // LOCK is always allowed.
        Op::Write(CR, CR_LOCK),
        Op::Write(KEYR, KEY1),
        Op::Write(KEYR, KEY2),
        // §3.5.3 step 1: no operation ongoing
        Op::WaitClear { addr: SR, mask: SR_BSY, polls: POLLS },
        // stale flags cleared (rc_w1), so the check below is this erase's
        Op::Write(SR, SR_EOP | SR_ERRORS),
        // steps 2 and 3: SER and SNB, then STRT
        Op::Write(CR, cr),
        Op::Write(CR, cr | CR_STRT),
        // step 4. Meanwhile any fetch from flash stalls (§3.5); this loop
        // may well spin from the instruction cache, interrupts cannot.
        Op::WaitClear { addr: SR, mask: SR_BSY, polls: POLLS },
        Op::Write(CR, CR_LOCK),
        Op::WaitClear { addr: SR, mask: SR_ERRORS, polls: 1 },
    ]
}
