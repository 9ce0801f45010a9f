//! TIM1, the advanced-control timer (RM0383 chapter 12), edge-aligned up-counting only.
//! The register decoding is in `tim1/regs.rs`, the channels in `tim1/oc.rs`.

mod burst;
mod fast;
mod oc;
mod regs;

use crate::bits::{cr2, dier};
use crate::timebase::{Tick, TimeBase};
use crate::PwmModeSwitch;
use oc::OcChannel;

/// What raised an update event.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Source {
    /// Counter overflow with the repetition counter at 0.
    Overflow,
    /// Software UG (EGR).
    Ug,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Tim1 {
    pub(crate) tb: TimeBase,
    ckd: u32,
    cr2: u32,
    dier: u32,
    pub(crate) ch: [OcChannel; 2],
    /// CCMR1 bits stored as written (OCxFE has no effect without a trigger input).
    ccmr1_fe: u32,
    ccer: u32,
    /// TIMx_RCR (REP[7:0], §12.4.13) and the repetition down-counter REP_CNT (§12.3.3).
    rcr: u32,
    rep_cnt: u32,
    bdtr: u32,
    dcr: u32,
    /// DMA index of TIMx_DMAR accesses: 0..=DBL (§12.4.20).
    burst_idx: u32,
    policy: PwmModeSwitch,
    /// Update (UEV) and UG pulses raised by register writes, seen by TRGO next cycle.
    pending_uev: bool,
    pending_ug: bool,
    /// TRGO level this cycle (§12.4.2 MMS).
    pub(crate) trgo: bool,
    /// The update DMA request line: set at an update event with UDE, cleared by the DMA
    /// acknowledge of the request (or of the last DMAR access of a burst).
    pub(crate) dma_req: bool,
    /// Update DMA requests raised while one was still pending (merged, hence lost).
    pub(crate) dma_overruns: u64,
    /// OC1/OC2 pin levels, and whether they changed since last taken.
    pub(crate) pins: [bool; 2],
    pub(crate) pins_dirty: bool,
}

impl Tim1 {
    pub fn new(policy: PwmModeSwitch) -> Tim1 {
        Tim1 {
            tb: TimeBase::new(0xFFFF),
            ckd: 0,
            cr2: 0,
            dier: 0,
            ch: [OcChannel::default(); 2],
            ccmr1_fe: 0,
            ccer: 0,
            rcr: 0,
            rep_cnt: 0,
            bdtr: 0,
            dcr: 0,
            burst_idx: 0,
            policy,
            pending_uev: false,
            pending_ug: false,
            trgo: false,
            dma_req: false,
            dma_overruns: 0,
            pins: [false; 2],
            pins_dirty: false,
        }
    }

    /// One CK_INT cycle.
    pub fn step(&mut self) {
        let uev_before = std::mem::take(&mut self.pending_uev);
        let ug = std::mem::take(&mut self.pending_ug);
        let mut cc1_match = false;
        if self.tb.latch_enable() {
            match self.tb.clock() {
                Tick::Idle => {}
                // A count that lands neither on 0 nor on a compare value changes no
                // comparison result and matches nothing (§12.3.9-10): nothing to do.
                Tick::Count if self.tb.cnt != 0 && self.ch.iter().all(|c| c.ccr_active != self.tb.cnt) => {}
                Tick::Count => cc1_match = self.ticked(),
                Tick::Overflow => {
                    self.overflow();
                    cc1_match = self.ticked();
                }
            }
        }
        let uev = uev_before || std::mem::take(&mut self.pending_uev);
        self.trgo = match cr2::MMS.get(self.cr2) {
            cr2::MMS_RESET => ug,
            cr2::MMS_ENABLE => self.tb.counting(),
            cr2::MMS_UPDATE => uev,
            cr2::MMS_COMPARE_PULSE => cc1_match,
            cr2::MMS_OC1REF => self.ch[0].oc_ref,
            _ => self.ch[1].oc_ref,
        };
    }

    /// Counter overflow: "the repetition counter is decremented at each counter overflow
    /// in upcounting mode" and the update event happens when it is 0 (§12.3.3; SR.UIF
    /// "at overflow ... regarding the repetition counter value (update if repetition
    /// counter = 0) and if UDIS = 0", §12.4.5).
    fn overflow(&mut self) {
        if self.rep_cnt == 0 {
            if !self.tb.udis {
                self.update_event(Source::Overflow);
            }
        } else {
            self.rep_cnt -= 1;
        }
    }

    /// A counter tick: compare both channels with the new CNT. Returns CC1's match.
    fn ticked(&mut self) -> bool {
        let (cnt, arr) = (self.tb.cnt, self.tb.arr_active);
        let m = self.ch[0].tick(cnt, arr, self.policy);
        self.ch[1].tick(cnt, arr, self.policy);
        self.refresh_pins();
        m
    }

    /// Re-evaluate both channels after a non-tick change of CNT, CCRx or ARR.
    fn reeval(&mut self) {
        let (cnt, arr) = (self.tb.cnt, self.tb.arr_active);
        for ch in &mut self.ch {
            ch.reeval(cnt, arr, self.policy);
        }
        self.refresh_pins();
    }

    /// The update event (§12.3.2, §12.3.3, §12.4.1): shadows take their preloads
    /// (PSC, ARR, CCRx), REP_CNT is reloaded from RCR, UIF is set and the update DMA
    /// request raised (UDE) unless URS = 1 and the source is UG, OPM clears CEN.
    fn update_event(&mut self, src: Source) {
        self.tb.load_shadows();
        for ch in &mut self.ch {
            ch.update_event();
        }
        self.rep_cnt = self.rcr;
        if src == Source::Overflow || !self.tb.urs {
            self.tb.uif = true;
            if dier::UDE.on(self.dier) {
                self.raise_dma_request();
            }
        }
        if self.tb.opm {
            self.tb.stop();
        }
        self.pending_uev = true;
    }

    /// UG (§12.4.6): counter and prescaler counter re-initialised even when UDIS = 1; the
    /// update event itself only when UDIS = 0 (§12.4.1 UDIS).
    fn ug(&mut self) {
        let uev = self.tb.ug();
        self.pending_ug = true;
        if uev {
            self.update_event(Source::Ug);
        }
        self.reeval();
    }

    /// OCx = OCxREF xor CCxP when CCxE = 1 and MOE = 1 (§12.4.9 table "Output control
    /// bits for complementary OCx and OCxN channels with break feature", rows with
    /// CCxNE = 0); otherwise not driven by the timer, reported low (board pull-downs).
    fn refresh_pins(&mut self) {
        use crate::bits::{bdtr, ccer};
        let moe = bdtr::MOE.on(self.bdtr);
        for (i, ch) in self.ch.iter().enumerate() {
            let c = i as u32;
            let level = moe && ccer::cce(c).on(self.ccer) && (ch.oc_ref ^ ccer::ccp(c).on(self.ccer));
            if level != self.pins[i] {
                self.pins[i] = level;
                self.pins_dirty = true;
            }
        }
    }
}
