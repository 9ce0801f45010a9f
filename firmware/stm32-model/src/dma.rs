//! DMA2 stream 5 (RM0383 chapter 9) as TIM1_UP's memory-to-peripheral channel: direct
//! mode, single transfers, DIR = 01, CHSEL = 6. "DMA2 request mapping" (§9.3.3/§9.3.4,
//! RM0090 §10.3.3 Table 43): stream 5, channel 6 = TIM1_UP (also checked against
//! stm32-metapac's DMA metadata, in `polyturn-regs`' tests).

mod regs;

use crate::bits::{dma_cr, dma_fcr, dma_isr};

/// One transfer to perform: read `size` bytes at `mem`, write them to `par`.
pub(crate) struct Transfer {
    pub mem: u32,
    pub size: u32,
    pub par: u32,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Dma {
    /// S5CR as written, without EN.
    cr: u32,
    en: bool,
    /// EN written 0 while a transfer was in flight: EN reads 1 until it completes.
    disabling: bool,
    /// NDTR as programmed, and the live down-counter.
    programmed: u32,
    ndtr: u32,
    par: u32,
    m0ar: u32,
    m1ar: u32,
    /// FTH and FEIE (DMDIS must stay 0: direct mode).
    fcr: u32,
    /// Internal memory pointer, in items from M0AR.
    item: u32,
    /// HISR bits of stream 5.
    flags: u32,
    /// Cycle at which the transfer in flight lands, `u64::MAX` when idle.
    pub next_due: u64,
}

impl Dma {
    pub fn new() -> Dma {
        Dma {
            cr: 0,
            en: false,
            disabling: false,
            programmed: 0,
            ndtr: 0,
            par: 0,
            m0ar: 0,
            m1ar: 0,
            fcr: dma_fcr::FTH.val(0b01),
            item: 0,
            flags: 0,
            next_due: u64::MAX,
        }
    }

    /// Whether a new request can be served (stream enabled and not being disabled).
    pub fn accepts(&self) -> bool {
        self.en && !self.disabling
    }

    pub fn idle(&self) -> bool {
        self.next_due == u64::MAX
    }

    /// Start serving a request: its transfer lands at `at`.
    pub fn schedule(&mut self, at: u64) {
        self.next_due = at;
    }

    fn size(&self) -> u32 {
        1 << dma_cr::PSIZE.get(self.cr)
    }

    /// The transfer in flight. Memory pointer: M0AR + item·MSIZE with MINC, M0AR without
    /// (§9.3.7 "Pointer incrementation"); MSIZE = PSIZE in direct mode (§9.5.5 MSIZE).
    pub fn current(&self) -> Transfer {
        let size = self.size();
        let step = if dma_cr::MINC.on(self.cr) { size } else { 0 };
        Transfer { mem: self.m0ar.wrapping_add(self.item * step), size, par: self.par }
    }

    /// The transfer landed: NDTR decrements (§9.3.2 "post-decrement of DMA_SxNDTR"), HTIF
    /// at half (§9.4 "half-transfer"), TCIF at 0; circular mode reloads NDTR and the
    /// pointer (§9.3.8), normal mode stops the stream (§9.5.5 EN "cleared by hardware on
    /// a DMA end of transfer"). A pending software disable takes effect now and sets
    /// TCIF (§9.3.14 "DMA transfer suspension").
    pub fn finish(&mut self) {
        self.next_due = u64::MAX;
        self.item += 1;
        self.ndtr -= 1;
        if self.ndtr == self.programmed / 2 {
            self.flags |= dma_isr::htif(5).mask();
        }
        if self.ndtr == 0 {
            self.flags |= dma_isr::tcif(5).mask();
            if dma_cr::CIRC.on(self.cr) {
                self.ndtr = self.programmed;
                self.item = 0;
            } else {
                self.en = false;
            }
        }
        if self.disabling {
            self.disabling = false;
            self.en = false;
            self.flags |= dma_isr::tcif(5).mask();
        }
    }

    /// NDTR as last programmed (what circular mode reloads).
    pub fn programmed_len(&self) -> u32 {
        self.programmed
    }

    pub fn quiet_cycles(&self, now: u64) -> u64 {
        self.next_due.saturating_sub(now + 1)
    }
}
