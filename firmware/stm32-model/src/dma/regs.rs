//! DMA2 stream 5 register reads and writes (RM0383 §9.5).

use super::Dma;
use crate::addr::{dma_off, DMA2, PERIPH_WINDOW, TIM1};
use crate::bits::{dma_cr, dma_fcr, dma_isr};
use crate::unmodelled;

impl Dma {
    pub fn write(&mut self, o: u32, v: u32) {
        let only = |reg: &str, allowed: u32| {
            if v & !allowed != 0 {
                let a = DMA2 + o;
                unmodelled(&format!("write {v:#x} to DMA2_{reg} ({a:#010x}) sets bits {:#x}", v & !allowed));
            }
        };
        let flag_bits = (4..8).fold(0, |m, s| {
            m | [dma_isr::feif(s), dma_isr::dmeif(s), dma_isr::teif(s), dma_isr::htif(s), dma_isr::tcif(s)]
                .iter()
                .fold(0, |m, f| m | f.mask())
        });
        let locked = self.en || self.disabling;
        match o {
            dma_off::LISR | dma_off::HISR => unmodelled("write to DMA2_LISR/HISR, which are read-only (§9.5.1-2)"),
            dma_off::LIFCR => only("LIFCR", flag_bits),
            dma_off::HIFCR => {
                only("HIFCR", flag_bits);
                self.flags &= !v;
            }
            o if o == dma_off::sxcr(5) => {
                if locked {
                    // "These bits are protected and can be written only if EN is '0'"
                    // (§9.5.5); writing EN = 0 asks the stream to stop after the
                    // current transfer (§9.3.14).
                    if !dma_cr::EN.on(v) {
                        if self.idle() {
                            self.en = false;
                            self.flags |= dma_isr::tcif(5).mask();
                        } else {
                            self.disabling = true;
                        }
                    }
                    return;
                }
                let allowed = [
                    dma_cr::EN,
                    dma_cr::DMEIE,
                    dma_cr::TEIE,
                    dma_cr::HTIE,
                    dma_cr::TCIE,
                    dma_cr::DIR,
                    dma_cr::CIRC,
                    dma_cr::MINC,
                    dma_cr::PSIZE,
                    dma_cr::MSIZE,
                    dma_cr::PL,
                    dma_cr::CHSEL,
                ];
                only("S5CR (PFCTRL, PINC, PINCOS, DBM, CT, bursts)", allowed.iter().fold(0, |m, f| m | f.mask()));
                self.cr = v & !dma_cr::EN.mask();
                if dma_cr::EN.on(v) {
                    self.enable();
                }
            }
            o if o == dma_off::sxndtr(5) => {
                only("S5NDTR", dma_fcr::NDT.mask());
                if !locked {
                    self.programmed = v;
                    self.ndtr = v;
                }
            }
            o if o == dma_off::sxpar(5) && !locked => self.par = v,
            o if o == dma_off::sxm0ar(5) && !locked => self.m0ar = v,
            o if o == dma_off::sxm1ar(5) && !locked => self.m1ar = v,
            o if o == dma_off::sxfcr(5) => {
                only("S5FCR (FIFO mode)", dma_fcr::FTH.mask() | dma_fcr::FS.mask() | dma_fcr::FEIE.mask());
                if !locked {
                    self.fcr = v & (dma_fcr::FTH.mask() | dma_fcr::FEIE.mask());
                }
            }
            o if o == dma_off::sxpar(5) || o == dma_off::sxm0ar(5) || o == dma_off::sxm1ar(5) => {}
            _ => unmodelled(&format!("DMA2 register at {:#010x} (only stream 5 is modelled)", DMA2 + o)),
        }
    }

    /// EN written 1 with the stream idle (§9.3.17 "Stream configuration procedure").
    fn enable(&mut self) {
        let cr = self.cr;
        if dma_cr::DIR.get(cr) != dma_cr::DIR_M2P || dma_cr::CHSEL.get(cr) != 6 {
            unmodelled("DMA2_S5CR (0x40026488): stream 5 enabled with DIR != 01 or CHSEL != 6 (only TIM1_UP memory-to-peripheral)");
        }
        let psize = dma_cr::PSIZE.get(cr);
        if psize != dma_cr::SIZE_HALF && psize != dma_cr::SIZE_WORD {
            unmodelled("DMA2_S5CR (0x40026488) PSIZE: timer registers take half-words or words only");
        }
        if !(TIM1..TIM1 + PERIPH_WINDOW).contains(&self.par) {
            unmodelled(&format!("DMA2_S5PAR (0x40026490) = {:#010x}: only TIM1 registers are modelled", self.par));
        }
        if self.flags != 0 {
            // §9.5.5 EN: "Before setting EN bit to '1' to start a new transfer, the event
            // flags corresponding to the stream in DMA_LISR or DMA_HISR register must be
            // cleared."
            unmodelled(
                "DMA2_S5CR (0x40026488): stream 5 enabled with HISR flags still set (clear them through HIFCR first, §9.5.5; a software disable sets TCIF, §9.3.14)",
            );
        }
        if self.ndtr == 0 {
            // NDTR is "reloaded automatically with the previously programmed value ...
            // when the stream is enabled again" (§9.5.6).
            self.ndtr = self.programmed;
        }
        if self.ndtr == 0 {
            unmodelled("DMA2_S5CR (0x40026488): stream 5 enabled with NDTR = 0");
        }
        // "In direct mode, MSIZE is forced by hardware to the same value as PSIZE as soon
        // as bit EN = '1'" (§9.5.5 MSIZE).
        self.cr = (cr & !dma_cr::MSIZE.mask()) | dma_cr::MSIZE.val(psize);
        self.item = 0;
        self.en = true;
    }

    pub fn read(&self, o: u32) -> u32 {
        match o {
            dma_off::LISR => 0,
            dma_off::HISR => self.flags,
            dma_off::LIFCR | dma_off::HIFCR => 0,
            o if o == dma_off::sxcr(5) => self.cr | dma_cr::EN.val((self.en || self.disabling) as u32),
            o if o == dma_off::sxndtr(5) => self.ndtr,
            o if o == dma_off::sxpar(5) => self.par,
            o if o == dma_off::sxm0ar(5) => self.m0ar,
            o if o == dma_off::sxm1ar(5) => self.m1ar,
            // FS = 100 "FIFO empty" as at reset (reset value 0x21, §9.5.10).
            o if o == dma_off::sxfcr(5) => self.fcr | dma_fcr::FS.val(0b100),
            _ => unmodelled(&format!("read of DMA2 register at {:#010x}", DMA2 + o)),
        }
    }
}
