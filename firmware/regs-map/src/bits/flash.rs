//! Flash interface bit fields (RM0383 §3.8).

/// FLASH_KEYR (RM0383 §3.8.2): the unlock keys, written in this order (§3.5.1).
pub mod flash_keyr {
    pub const KEY1: u32 = 0x4567_0123;
    pub const KEY2: u32 = 0xCDEF_89AB;
}

/// FLASH_SR (RM0383 §3.8.4): end of operation, the error flags, busy.
pub mod flash_sr {
    use super::super::{bit, Field};
    pub const EOP: Field = bit(0);
    pub const OPERR: Field = bit(1);
    pub const WRPERR: Field = bit(4);
    pub const PGAERR: Field = bit(5);
    pub const PGPERR: Field = bit(6);
    pub const PGSERR: Field = bit(7);
    /// PCROP read error (RM0383 §3.8.4; not in the SVD the tests check against)
    pub const RDERR: Field = bit(8);
    pub const BSY: Field = bit(16);
    /// Every error flag: OPERR, WRPERR, PGAERR, PGPERR, PGSERR, RDERR
    /// (each cleared by writing 1, §3.8.4).
    pub const ERRORS: u32 = OPERR.mask() | WRPERR.mask() | PGAERR.mask() | PGPERR.mask() | PGSERR.mask() | RDERR.mask();
}

/// FLASH_CR (RM0383 §3.8.5): program, sector and mass erase, the sector, the
/// program size, start, the end-of-operation interrupt, lock.
pub mod flash_cr {
    use super::super::{bit, Field};
    pub const PG: Field = bit(0);
    pub const SER: Field = bit(1);
    pub const MER: Field = bit(2);
    pub const SNB: Field = Field::new(3, 4);
    pub const PSIZE: Field = Field::new(8, 2);
    /// PSIZE = 10: program ×32
    pub const PSIZE_X32: u32 = 0b10;
    pub const STRT: Field = bit(16);
    pub const EOPIE: Field = bit(24);
    pub const LOCK: Field = bit(31);
}
