//! TIM11, a one-channel general-purpose timer (RM0383 chapter 14, TIM10/11 registers
//! §14.5), used as a plain up-counter whose update events are the control tick.

use crate::bits::{cr1, dier, egr, sr};
use crate::timebase::{Tick, TimeBase};
use crate::unmodelled;

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Tim11 {
    tb: TimeBase,
    ckd: u32,
    dier: u32,
    /// Update events so far (overflows and UG).
    pub updates: u64,
    /// Times UIF was set (what the update interrupt sees): like `updates`, less the UGs
    /// made with URS = 1.
    pub uif_sets: u64,
}

impl Tim11 {
    pub fn new() -> Tim11 {
        Tim11 { tb: TimeBase::new(0xFFFF), ckd: 0, dier: 0, updates: 0, uif_sets: 0 }
    }

    /// One CK_INT cycle: an update event at every overflow, i.e. every
    /// (PSC+1)·(ARR+1) cycles once running (§14.3.1, §14.3.2 "Upcounting mode").
    pub fn step(&mut self) {
        if self.tb.latch_enable() && self.tb.clock() == Tick::Overflow && !self.tb.udis {
            self.update_event(true);
        }
    }

    /// Update event (§14.3.2): shadows reloaded, UIF set unless URS = 1 and UG.
    fn update_event(&mut self, overflow: bool) {
        self.tb.load_shadows();
        self.updates += 1;
        if overflow || !self.tb.urs {
            self.tb.uif = true;
            self.uif_sets += 1;
        }
    }

    pub fn quiet_cycles(&self) -> u64 {
        if !self.tb.enable_settled() {
            0
        } else if !self.tb.counting() {
            u64::MAX
        } else {
            self.tb.pulses_before_tick(self.tb.ticks_to_wrap())
        }
    }

    /// Stopped: stepping changes nothing.
    pub fn idle(&self) -> bool {
        !self.tb.counting() && self.tb.enable_settled()
    }

    pub fn skip(&mut self, n: u64) {
        if self.tb.counting() {
            self.tb.skip_pulses(n);
        }
    }

    pub fn write(&mut self, o: u32, v: u32) {
        use crate::addr::off;
        let only = |reg: &str, allowed: u32| crate::only_bits("TIM11", crate::addr::TIM11, o, reg, v, allowed);
        match o {
            off::CR1 => {
                // TIM10/11_CR1 (§14.5.1): CKD, ARPE, URS, UDIS, CEN; bits 6:3 (where
                // TIM1 has OPM, DIR, CMS) are reserved on TIM10/11.
                only("CR1", cr1::CEN.mask() | cr1::UDIS.mask() | cr1::URS.mask() | cr1::ARPE.mask() | cr1::CKD.mask());
                // (OPM is reserved here: `only` above keeps it 0)
                self.tb.write_cr1(v);
                self.ckd = cr1::CKD.get(v);
            }
            off::DIER => {
                only("DIER", dier::UIE.mask() | dier::ccie(0).mask());
                self.dier = v;
            }
            off::SR => self.tb.write_uif(v),
            off::EGR => {
                only("EGR (only UG)", egr::UG.mask());
                if egr::UG.on(v) && self.tb.ug() {
                    self.update_event(false);
                }
            }
            off::CNT => {
                only("CNT", 0xFFFF);
                self.tb.cnt = v;
            }
            off::PSC => {
                only("PSC", 0xFFFF);
                self.tb.psc = v;
            }
            off::ARR => {
                only("ARR", 0xFFFF);
                self.tb.write_arr(v);
            }
            o if o <= off::OR => only("register not modelled (must stay 0)", 0),
            _ => unmodelled(&format!("TIM11 register at {:#010x}", crate::addr::TIM11 + o)),
        }
    }

    pub fn read(&self, o: u32) -> u32 {
        use crate::addr::off;
        match o {
            off::CR1 => self.tb.cr1() | cr1::CKD.val(self.ckd),
            off::DIER => self.dier,
            off::SR => sr::UIF.val(self.tb.uif as u32),
            off::EGR => 0,
            off::CNT => self.tb.cnt,
            off::PSC => self.tb.psc,
            off::ARR => self.tb.arr,
            _ => unmodelled(&format!("read of TIM11 register at {:#010x}", crate::addr::TIM11 + o)),
        }
    }
}
