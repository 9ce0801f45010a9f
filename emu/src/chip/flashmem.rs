//! The flash array under the CPU: programming and erase act on the bytes the
//! CPU executes and reads (`Machine` maps them read/execute; a store to them is
//! caught and handed here), and a flash operation stalls the CPU until BSY
//! clears: code and vectors are fetched from flash, and "any attempt to read the
//! Flash memory ... while it is being written or erased causes the bus to stall"
//! (RM0383 §3.5.1).

use super::Chip;
use crate::image::{FLASH_BASE, FLASH_SIZE};
use polyturn_stm32_model::flash::sector_kib;

/// A store unicorn performs after its hook: the bytes the cell must hold instead
/// (the programmed value, or the old one), put back before anything reads them.
pub struct Fixup {
    off: usize,
    bytes: [u8; 4],
    len: usize,
}

impl Chip {
    fn flash_bytes(&mut self) -> &mut [u8] {
        // SAFETY: `flash_mem` points at the machine's FLASH_SIZE bytes, which live
        // as long as the machine (and this chip inside it); unicorn writes them only
        // inside a store, never while this runs
        unsafe { std::slice::from_raw_parts_mut(self.flash_mem, FLASH_SIZE as usize) }
    }

    /// Puts back what the last stores to flash must have left.
    pub fn apply_fixups(&mut self) {
        for f in std::mem::take(&mut self.fixups) {
            self.flash_bytes()[f.off..f.off + f.len].copy_from_slice(&f.bytes[..f.len]);
        }
    }

    /// A CPU store of `size` bytes at flash address `addr`: programs (the value
    /// ANDed into the cell, `Flash::program`) or leaves the cell as it was.
    pub fn flash_store(&mut self, addr: u32, size: u32, value: u32) {
        self.apply_fixups();
        self.sync();
        let off = (addr - FLASH_BASE) as usize;
        let len = (size as usize).min(4);
        let programs = self.flash.program(addr, size);
        let mut bytes = [0u8; 4];
        bytes[..len].copy_from_slice(&self.flash_bytes()[off..off + len]);
        if programs {
            for (i, b) in bytes[..len].iter_mut().enumerate() {
                *b &= (value >> (8 * i)) as u8;
            }
        }
        self.fixups.push(Fixup { off, bytes, len });
        self.stall_for_flash();
    }

    /// After a FLASH_CR write: an erase that started clears its sector to 0xFF.
    pub fn flash_erased(&mut self) {
        while self.erases_applied < self.flash.erases.len() {
            let sector = self.flash.erases[self.erases_applied].sector;
            let start = (0..sector).map(|s| sector_kib(s) as usize * 1024).sum::<usize>();
            let len = sector_kib(sector) as usize * 1024;
            self.flash_bytes()[start..start + len].fill(0xFF);
            self.erases_applied += 1;
        }
        self.stall_for_flash();
    }

    /// The CPU waits out a flash operation: the time it takes passes at once.
    fn stall_for_flash(&mut self) {
        let Some(until) = self.flash.busy_until_ns() else { return };
        let ns = until.saturating_sub(self.flash.now_ns());
        let cycles = (ns as u128 * self.sysclk() as u128).div_ceil(1_000_000_000) as u64;
        self.stall(cycles);
    }

    /// The CPU stalled for `cycles`: time passes at once, the models with it.
    pub(crate) fn stall(&mut self, cycles: u64) {
        self.stalled += cycles;
        self.now += cycles;
        self.blk += cycles;
        self.sync();
    }
}
