//! The MCU: bus decoding, SRAM, the per-cycle schedule and the fast path.

mod bus;
mod tim9;

use crate::addr;
use crate::dma::Dma;
use crate::tim1::Tim1;
use crate::tim11::Tim11;
use crate::tim2::Tim2;
use crate::tim9::Tim9;
use crate::{EncoderCapture, PwmModeSwitch};

/// Figures the manual does not give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Params {
    /// CK_INT cycles from a DMA request (or from the previous transfer of the same burst)
    /// to the moment the transfer's write lands in TIM1. RM0383 §9 gives no timing;
    /// default 6: one cycle to sample the request, one to arbitrate (§9.3.4), and an
    /// AHB→APB2 write of a value the direct mode already preloaded ("the DMA preloads
    /// only one data from the memory ... to ensure an immediate data transfer", §9.2),
    /// about 4 cycles through the bridge. An estimate: sweep it in tests. A request raised
    /// by a CPU write lands no earlier than the next cycle, whatever this value.
    pub dma_latency_cycles: u32,
    /// CK_INT cycles between a TRGI rising edge and the TIM2 count it causes in external
    /// clock mode 1. RM0383 §13.3.3 only says the delay "is due to the
    /// resynchronization circuit"; default 2 (a two-flip-flop synchroniser). At most 62.
    pub tim2_resync_cycles: u32,
    /// OCxREF on a switch into PWM mode; see [`PwmModeSwitch`].
    pub pwm_mode_switch: PwmModeSwitch,
    /// When DMA2_S5NDTR counts a word; see [`NdtrReading`].
    pub ndtr: NdtrReading,
    /// What TIM3's channel 1 latches on the A edge it also counts; see
    /// [`EncoderCapture`] (for the event-driven `chip::gptimer`, which the emulator
    /// builds with it).
    pub encoder_capture: EncoderCapture,
}

/// Two readings of when NDTR counts a word in direct mode, memory to
/// peripheral. The firmware must work on both (`stepgen::ndtr_lead`); the
/// bench tells which one the silicon follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NdtrReading {
    /// after the word is written to the peripheral: "post-decrement of the
    /// DMA_SxNDTR register" once the transfer is done (§9.3.2, §9.3.3)
    AfterTransfer,
    /// when direct mode preloads the word from memory ahead of the request
    /// ("the DMA preloads only one data from the memory", §9.2; §9.3.12):
    /// NDTR reads one less while a word is preloaded
    AtPreload,
}

impl Default for Params {
    fn default() -> Params {
        Params {
            dma_latency_cycles: 6,
            tim2_resync_cycles: 2,
            pwm_mode_switch: PwmModeSwitch::Reevaluate,
            ndtr: NdtrReading::AfterTransfer,
            encoder_capture: EncoderCapture::CountBefore,
        }
    }
}

/// PA8 carries TIM1_CH1 (OC1), PA9 TIM1_CH2 (OC2); PA2 TIM9_CH1, PA3 TIM9_CH2 (AF3,
/// STM32F411xC/E datasheet, alternate function mapping).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PinId {
    Pa8,
    Pa9,
    Pa2,
    Pa3,
}

/// The pins in the order of `Mcu::pins` (and of edges made in the same cycle).
const PIN_ORDER: [PinId; 4] = [PinId::Pa8, PinId::Pa9, PinId::Pa2, PinId::Pa3];

/// A change of a pin's level: made by step number `cycle` (so `Mcu::cycle() == cycle`
/// right after it), or by a register write made while `Mcu::cycle() == cycle`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    pub cycle: u64,
    pub pin: PinId,
    pub high: bool,
}

/// The modelled MCU. Equality compares the whole modelled state (registers, internal
/// counters, SRAM, edges), not caches.
#[derive(Clone, Debug)]
pub struct Mcu {
    params: Params,
    cycle: u64,
    tim1: Tim1,
    tim2: Tim2,
    tim11: Tim11,
    tim9: Tim9,
    dma: Dma,
    sram: Vec<u8>,
    edges: Vec<Edge>,
    pins: [bool; 4],
    dma_lost: u64,
    /// DMA2 stream 5's transfers so far (an emulator bounds the CPU's bus
    /// waits by them)
    dma_transfers: u64,
    /// Nothing counts, nothing is pending: a step only advances the cycle count.
    quiescent: bool,
    /// Direct mode, memory to peripheral: the stream reads its next item from
    /// memory before the request comes (RM0383 §9.3.12: "the DMA preloads only
    /// one data from the memory to the internal FIFO to ensure an immediate data
    /// transfer as soon as a DMA request is triggered"): when it is enabled and
    /// after each transfer. `None` while the stream is off.
    prefetched: Option<u32>,
    /// The cycle in which TIM9 last set UIF (what its update interrupt
    /// answers), by an overflow or a UG, for an emulator timing the
    /// handler from the event
    tim9_uif_at: u64,
}

impl PartialEq for Mcu {
    fn eq(&self, o: &Mcu) -> bool {
        (self.params, self.cycle, &self.tim1, &self.tim2, &self.tim11, &self.dma)
            == (o.params, o.cycle, &o.tim1, &o.tim2, &o.tim11, &o.dma)
            && (&self.sram, &self.edges, self.pins, self.dma_lost) == (&o.sram, &o.edges, o.pins, o.dma_lost)
            && self.prefetched == o.prefetched
            && self.tim9 == o.tim9
    }
}

impl Eq for Mcu {}

impl Mcu {
    /// Every register at its reset value, SRAM zeroed, cycle 0.
    pub fn new(params: Params) -> Mcu {
        Mcu {
            params,
            cycle: 0,
            tim1: Tim1::new(params.pwm_mode_switch),
            tim2: Tim2::new(params.tim2_resync_cycles),
            tim11: Tim11::new(),
            tim9: Tim9::new(),
            dma: Dma::new(),
            sram: vec![0; addr::SRAM_SIZE as usize],
            edges: Vec::new(),
            pins: [false; 4],
            tim9_uif_at: 0,
            dma_lost: 0,
            dma_transfers: 0,
            quiescent: false,
            prefetched: None,
        }
    }

    pub fn cycle(&self) -> u64 {
        self.cycle
    }
    pub fn pa8(&self) -> bool {
        self.pins[0]
    }
    pub fn pa9(&self) -> bool {
        self.pins[1]
    }
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }
    /// TIM11 update events so far: every overflow (§14.3.2) and every UG (§14.5.4).
    pub fn tim11_updates(&self) -> u64 {
        self.tim11.updates
    }
    /// How many of those set TIM11's UIF (a UG with URS = 1 does not, §14.5.1), i.e. the
    /// update interrupts the control tick would take with UIE = 1.
    pub fn tim11_uif_sets(&self) -> u64 {
        self.tim11.uif_sets
    }
    /// TIM1 update DMA requests that were not served: raised while the stream was
    /// disabled, or while the previous one was still pending (merged).
    pub fn dma_requests_lost(&self) -> u64 {
        self.dma_lost + self.tim1.dma_overruns
    }

    /// DMA2 stream 5's transfers so far: each a read of SRAM and a write of
    /// TIM1's DMAR on the bus matrix the CPU shares (§2.1).
    pub fn dma_transfers(&self) -> u64 {
        self.dma_transfers
    }

    /// Advance one CK_INT cycle: TIM1, then TIM2 sampling TIM1's TRGO of this cycle,
    /// then TIM11, TIM9, then any DMA transfer that lands in this cycle.
    #[inline]
    pub fn step(&mut self) {
        self.cycle += 1;
        if self.quiescent {
            return;
        }
        self.tim1.step();
        self.tim2.step(self.tim1.trgo);
        self.tim11.step();
        let uif_sets = self.tim9.uif_sets;
        self.tim9.step();
        if self.tim9.uif_sets != uif_sets {
            self.tim9_uif_at = self.cycle;
        }
        self.sync_dma();
        while self.dma.next_due <= self.cycle {
            self.dma_transfer();
        }
        self.record_edges();
        self.quiescent = self.tim1.idle()
            && self.tim11.idle()
            && self.tim9.idle()
            && self.dma.idle()
            && self.tim2.idle(self.tim1.quiet_trgo());
    }

    /// Cycles from now in which only counters advance: no flag, request, transfer or
    /// pin edge. An emulator runs the CPU that long before it looks at the
    /// interrupt lines again (`emu/`).
    pub fn quiet_cycles(&self) -> u64 {
        self.tim1
            .quiet_cycles()
            .min(self.tim2.quiet_cycles(self.tim1.quiet_trgo()))
            .min(self.tim11.quiet_cycles())
            .min(self.tim9.quiet_cycles())
            .min(self.dma.quiet_cycles(self.cycle))
    }

    /// The SRAM the DMA reads, for an emulator to map as the CPU's RAM. The buffer
    /// never moves (it is allocated once, in `new`).
    pub fn sram_mut_ptr(&mut self) -> *mut u8 {
        self.sram.as_mut_ptr()
    }

    /// Step to `cycle`, skipping stretches where only counters advance.
    pub fn run_until(&mut self, cycle: u64) {
        while self.cycle < cycle {
            let quiet = self.quiet_cycles().min(cycle - self.cycle);
            if quiet == 0 {
                self.step();
            } else {
                self.cycle += quiet;
                self.tim1.skip(quiet);
                self.tim2.skip(quiet, self.tim1.trgo);
                self.tim11.skip(quiet);
                self.tim9.skip(quiet);
            }
        }
    }

    /// Connect TIM1's update request line to the stream: a request the stream cannot take
    /// (EN = 0) is lost; an accepted one lands `dma_latency_cycles` later.
    fn sync_dma(&mut self) {
        if self.tim1.dma_req {
            if !self.dma.accepts() {
                self.tim1.drop_dma_request();
                self.dma_lost += 1;
            } else if self.dma.idle() {
                self.dma.schedule(self.cycle + self.params.dma_latency_cycles as u64);
            }
        }
    }

    fn dma_transfer(&mut self) {
        let t = self.dma.current();
        let value = match self.prefetched.take() {
            Some(v) => v,
            None => self.sram_read(t.mem, t.size),
        };
        self.tim1.dma_write(t.par - addr::TIM1, value);
        self.dma_transfers += 1;
        self.dma.finish();
        self.prefetch();
        self.sync_dma();
    }

    /// Latches the stream's next item while it is enabled (see `prefetched`).
    pub(crate) fn prefetch(&mut self) {
        if !self.dma.accepts() {
            self.prefetched = None;
        } else if self.prefetched.is_none() {
            let t = self.dma.current();
            let in_sram = t.mem.wrapping_sub(addr::SRAM_BASE) < addr::SRAM_SIZE && t.mem.is_multiple_of(t.size);
            // (outside SRAM the transfer itself reports the access)
            self.prefetched = in_sram.then(|| self.sram_read(t.mem, t.size));
        }
    }

    #[inline]
    fn record_edges(&mut self) {
        if self.tim1.pins_dirty || self.tim9.pins_dirty {
            self.push_edges();
        }
    }

    #[cold]
    fn push_edges(&mut self) {
        self.tim1.pins_dirty = false;
        self.tim9.pins_dirty = false;
        let levels = [self.tim1.pins[0], self.tim1.pins[1], self.tim9.pins[0], self.tim9.pins[1]];
        for (i, pin) in PIN_ORDER.into_iter().enumerate() {
            let high = levels[i];
            if high != self.pins[i] {
                self.pins[i] = high;
                self.edges.push(Edge { cycle: self.cycle, pin, high });
            }
        }
    }
}
