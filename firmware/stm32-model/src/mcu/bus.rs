//! The bus: 32-bit CPU accesses decoded to a peripheral window or to SRAM.

use super::{Mcu, NdtrReading};
use crate::addr::{self, PERIPH_WINDOW};
use crate::unmodelled;

impl Mcu {
    pub(super) fn sram_index(&self, a: u32, size: u32) -> usize {
        let off = a.wrapping_sub(addr::SRAM_BASE);
        if a & (size - 1) != 0 || off >= addr::SRAM_SIZE {
            unmodelled(&format!("{size}-byte SRAM access at {a:#010x} (unaligned or outside SRAM)"));
        }
        off as usize
    }

    /// Little-endian read of `size` bytes (the Cortex-M4 and the DMA are little-endian).
    pub(super) fn sram_read(&self, a: u32, size: u32) -> u32 {
        let i = self.sram_index(a, size);
        self.sram[i..i + size as usize].iter().rev().fold(0, |v, &b| (v << 8) | b as u32)
    }

    /// 32-bit CPU write to a modelled register or to SRAM.
    pub fn write(&mut self, a: u32, value: u32) {
        match peripheral(a) {
            Some((addr::TIM1, o)) => self.tim1.write(o, value),
            Some((addr::TIM2, o)) => self.tim2.write(o, value),
            Some((addr::TIM11, o)) => self.tim11.write(o, value),
            Some((addr::TIM9, o)) => {
                // a UG with URS = 0 sets UIF from the write (§14.4.1, §14.4.5)
                let uif_sets = self.tim9.uif_sets;
                self.tim9.write(o, value);
                if self.tim9.uif_sets != uif_sets {
                    self.tim9_uif_at = self.cycle;
                }
            }
            Some((_, o)) => {
                self.dma.write(o, value);
                self.prefetch();
            }
            None => {
                let i = self.sram_index(a, 4);
                self.sram[i..i + 4].copy_from_slice(&value.to_le_bytes());
            }
        }
        self.quiescent = false;
        self.sync_dma();
        self.record_edges();
    }

    /// 32-bit CPU read. Only TIMx_DMAR has a side effect (it advances the burst index).
    pub fn read(&mut self, a: u32) -> u32 {
        match peripheral(a) {
            Some((addr::TIM1, o)) => self.tim1.read(o),
            Some((addr::TIM2, o)) => self.tim2.read(o),
            Some((addr::TIM11, o)) => self.tim11.read(o),
            Some((addr::TIM9, o)) => self.tim9.read(o),
            Some((_, o)) => self.dma_read(o),
            None => self.sram_read(a, 4),
        }
    }

    /// A DMA register; NDTR as `Params::ndtr` reads it: one ahead while a
    /// word is preloaded on `AtPreload` (in circular mode the count that
    /// reaches 0 there reloads, §9.3.8, so it reads the programmed length).
    fn dma_read(&self, o: u32) -> u32 {
        let v = self.dma.read(o);
        let ahead = self.params.ndtr == NdtrReading::AtPreload && self.prefetched.is_some();
        if o != crate::addr::dma_off::sxndtr(5) || !ahead {
            return v;
        }
        match v {
            0 => 0,
            1 => self.dma.programmed_len(),
            n => n - 1,
        }
    }
}

/// The peripheral window holding `a`, as (base, offset); `None` for SRAM; panics for
/// anything else.
fn peripheral(a: u32) -> Option<(u32, u32)> {
    if a & 3 != 0 {
        unmodelled(&format!("unaligned 32-bit access at {a:#010x}"));
    }
    for base in [addr::TIM1, addr::TIM2, addr::TIM11, addr::TIM9, addr::DMA2] {
        if (base..base + PERIPH_WINDOW).contains(&a) {
            return Some((base, a - base));
        }
    }
    if (addr::SRAM_BASE..addr::SRAM_BASE + addr::SRAM_SIZE).contains(&a) {
        return None;
    }
    unmodelled(&format!("address {a:#010x} is not a modelled peripheral or SRAM"))
}
