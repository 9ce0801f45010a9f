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

/// FLASH interface registers (RM0383 §2.3 Table 1, §3.8.7 register map).
const FLASH_R: u32 = 0x4002_3C00;
const KEYR: u32 = FLASH_R + 0x04;
const SR: u32 = FLASH_R + 0x0C;
const CR: u32 = FLASH_R + 0x10;
/// The unlock keys (§3.5.1).
const KEY1: u32 = 0x4567_0123;
const KEY2: u32 = 0xCDEF_89AB;
/// FLASH_SR (§3.8.4): EOP, the error flags (OPERR, WRPERR, PGAERR, PGPERR,
/// PGSERR, RDERR), BSY.
const SR_EOP: u32 = 1 << 0;
const SR_ERRORS: u32 = 0b1_1111_0010;
const SR_BSY: u32 = 1 << 16;
/// FLASH_CR (§3.8.5).
const CR_SER: u32 = 1 << 1;
const CR_SNB_SHIFT: u32 = 3;
const CR_PSIZE_X32: u32 = 0b10 << 8;
const CR_STRT: u32 = 1 << 16;
const CR_LOCK: u32 = 1 << 31;

/// The longest a 128 KiB sector erase takes at ×32 (DS10314, max).
pub const ERASE_MAX_US: u32 = 2_000_000;
/// The longest one 32-bit word takes to program (DS10314, t_prog max).
pub const WORD_PROGRAM_MAX_US: u32 = 100;

/// BSY is polled at least this many times, each poll a load, a test and a
/// branch (≥ 4 cycles), so the wait gives up no sooner than the longest
/// erase; the watchdog (`iwdg`) ends a flash that never finishes.
const POLLS: u32 = ERASE_MAX_US / 4 * (SYSCLK_HZ / 1_000_000);

/// Erases sector `sector` (0 to 7) at ×32 and locks FLASH_CR again. `Err`
/// from `regs::apply` names the step that failed: the BSY wait (index 3 or
/// 7) or the final error check (index 9).
pub fn erase_sector(sector: u8) -> [Op; 10] {
    let cr = CR_PSIZE_X32 | CR_SER | (sector as u32 & 0xF) << CR_SNB_SHIFT;
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
        // step 4. The CPU stalls at its first fetch from flash meanwhile.
        Op::WaitClear { addr: SR, mask: SR_BSY, polls: POLLS },
        Op::Write(CR, CR_LOCK),
        Op::WaitClear { addr: SR, mask: SR_ERRORS, polls: 1 },
    ]
}
