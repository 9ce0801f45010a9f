//! TIM2, 32-bit general-purpose timer (RM0383 chapter 13), used as a counter of TIM1's
//! trigger output: slave mode "external clock mode 1" on ITR0.
//!
//! ITR0 of TIM2 is TIM1's TRGO. RM0383 gives it in the table "TIMx internal trigger
//! connection" (§13.4.3, TIM2 row: ITR0 = TIM1); the text retrieved for this model is
//! the same IP's worked example, RM0090 §18.3.15 "Using one timer as prescaler for
//! another timer" (RM0383 §13.3.15): "To connect the TRGO1 output of Timer 1 to Timer 2,
//! Timer 2 must be configured in slave mode using ITR0 as internal trigger ... (writing
//! TS=000)", and RM0033 Figure 153 (TIM1 TRGO1 → TIM2 ITR0).

use crate::bits::{cr1, dier, egr, smcr, sr};
use crate::timebase::{Tick, TimeBase};
use crate::unmodelled;

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Tim2 {
    tb: TimeBase,
    ckd: u32,
    smcr: u32,
    dier: u32,
    /// TRGI history, bit i = TRGI level i cycles ago (bit 0: this cycle).
    hist: u64,
    /// Resynchronisation delay of TRGI before the edge detector, in CK_INT cycles.
    resync: u32,
}

fn ext_clock(smcr_v: u32) -> bool {
    smcr::SMS.get(smcr_v) == smcr::SMS_EXT_CLOCK_1
}

impl Tim2 {
    pub fn new(resync: u32) -> Tim2 {
        assert!(resync <= 62, "tim2_resync_cycles must be at most 62");
        Tim2 { tb: TimeBase::new(u32::MAX), ckd: 0, smcr: 0, dier: 0, hist: 0, resync }
    }

    /// One CK_INT cycle with TRGI (= TIM1 TRGO through ITR0) at `trgi`.
    /// External clock mode 1: "rising edges of the selected trigger (TRGI) clock the
    /// counter" (§13.4.3 SMS = 111); the edge reaches the counter after the
    /// resynchronisation delay the manual mentions but does not quantify (§13.3.3
    /// "External clock source mode 1": "The delay between the rising edge ... and the
    /// actual clock of the counter is due to the resynchronization circuit").
    pub fn step(&mut self, trgi: bool) {
        self.hist = (self.hist << 1) | trgi as u64;
        let run = self.tb.latch_enable();
        let pulse = if ext_clock(self.smcr) {
            let d = self.resync;
            (self.hist >> d) & 0b11 == 0b01
        } else {
            true
        };
        if run && pulse && self.tb.clock() == Tick::Overflow && !self.tb.udis {
            self.update_event(true);
        }
    }

    /// Update event (§13.3.2): shadows reloaded, UIF unless URS = 1 for UG, OPM stops.
    fn update_event(&mut self, overflow: bool) {
        self.tb.load_shadows();
        if overflow || !self.tb.urs {
            self.tb.uif = true;
        }
        if self.tb.opm {
            self.tb.stop();
        }
    }

    fn window_settled(&self, level: bool) -> bool {
        let mask = (1u64 << (self.resync + 2)) - 1;
        self.hist & mask == if level { mask } else { 0 }
    }

    /// Cycles that change nothing but CNT/prescaler, with TRGI held at `trgi`.
    pub fn quiet_cycles(&self, trgi: bool) -> u64 {
        if !self.tb.enable_settled() {
            return 0;
        }
        if ext_clock(self.smcr) {
            return if self.window_settled(trgi) { u64::MAX } else { 0 };
        }
        if !self.tb.counting() {
            return u64::MAX;
        }
        self.tb.pulses_before_tick(self.tb.ticks_to_wrap())
    }

    /// Nothing can change while TRGI stays at `trgi`: not counting CK_INT, and the TRGI
    /// history is all at that level (shifting it in again is a fixed point).
    pub fn idle(&self, trgi: bool) -> bool {
        self.tb.enable_settled()
            && (!self.tb.counting() || ext_clock(self.smcr))
            && self.hist == if trgi { u64::MAX } else { 0 }
    }

    pub fn skip(&mut self, n: u64, trgi: bool) {
        let fill = if n >= 64 { u64::MAX } else { (1u64 << n) - 1 };
        let shifted = if n >= 64 { 0 } else { self.hist << n };
        self.hist = shifted | if trgi { fill } else { 0 };
        if self.tb.counting() && !ext_clock(self.smcr) {
            self.tb.skip_pulses(n);
        }
    }

    pub fn write(&mut self, o: u32, v: u32) {
        use crate::addr::off;
        let only = |reg: &str, allowed: u32| crate::only_bits("TIM2", crate::addr::TIM2, o, reg, v, allowed);
        match o {
            off::CR1 => {
                if cr1::DIR.on(v) || cr1::CMS.get(v) != 0 {
                    unmodelled("TIM2_CR1 (0x40000000): only up-counting is modelled (DIR = 0, CMS = 00)");
                }
                only("CR1", 0x3FF & !(cr1::DIR.mask() | cr1::CMS.mask()));
                self.tb.write_cr1(v);
                self.ckd = cr1::CKD.get(v);
            }
            off::SMCR => {
                only("SMCR (only SMS and TS are modelled)", smcr::SMS.mask() | smcr::TS.mask());
                let sms = smcr::SMS.get(v);
                if sms != smcr::SMS_DISABLED && sms != smcr::SMS_EXT_CLOCK_1 {
                    unmodelled("TIM2_SMCR.SMS (0x40000008): only 000 and 111 (external clock mode 1)");
                }
                if smcr::TS.get(v) != smcr::TS_ITR0 {
                    unmodelled("TIM2_SMCR.TS (0x40000008): only ITR0 (TIM1 TRGO) is modelled");
                }
                self.smcr = v;
            }
            off::DIER => {
                only("DIER (only UIE)", dier::UIE.mask());
                self.dier = v;
            }
            off::SR => self.tb.write_uif(v),
            off::EGR => {
                only("EGR (only UG)", egr::UG.mask());
                if egr::UG.on(v) && self.tb.ug() {
                    self.update_event(false);
                }
            }
            off::CNT => self.tb.cnt = v,
            off::PSC => {
                only("PSC", 0xFFFF);
                self.tb.psc = v;
            }
            off::ARR => self.tb.write_arr(v),
            o if o <= off::OR => only("register not modelled (must stay 0)", 0),
            _ => unmodelled(&format!("TIM2 register at {:#010x}", crate::addr::TIM2 + o)),
        }
    }

    pub fn read(&self, o: u32) -> u32 {
        use crate::addr::off;
        match o {
            off::CR1 => self.tb.cr1() | cr1::CKD.val(self.ckd),
            off::SMCR => self.smcr,
            off::DIER => self.dier,
            off::SR => sr::UIF.val(self.tb.uif as u32),
            off::CNT => self.tb.cnt,
            off::PSC => self.tb.psc,
            off::ARR => self.tb.arr,
            off::CR2 | off::EGR => 0,
            _ => unmodelled(&format!("read of TIM2 register at {:#010x}", crate::addr::TIM2 + o)),
        }
    }
}
