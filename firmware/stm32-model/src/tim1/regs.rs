//! TIM1 register reads and writes (RM0383 §12.4). Bits that the model does not
//! implement must stay at their reset value (0); anything else panics.

use super::Tim1;
use crate::addr::off;
use crate::bits::{bdtr, ccer, ccmr, cr1, cr2, dcr, dier, egr, sr};
use crate::unmodelled;

/// Panics unless `value` only sets bits in `allowed`.
#[track_caller]
fn only(o: u32, reg: &str, value: u32, allowed: u32) {
    crate::only_bits("TIM1", crate::addr::TIM1, o, reg, value, allowed);
}

fn unknown(o: u32) -> ! {
    unmodelled(&format!("TIM1 register at {:#010x}", crate::addr::TIM1 + o))
}

impl Tim1 {
    pub fn write(&mut self, o: u32, v: u32) {
        let (cnt, arr, pol) = (self.tb.cnt, self.tb.arr_active, self.policy);
        match o {
            off::CR1 => self.write_cr1(o, v),
            off::CR2 => self.write_cr2(o, v),
            off::SMCR => only(o, "SMCR (slave mode controller)", v, 0),
            off::DIER => {
                // Interrupt enables are stored (SR flags are modelled, the NVIC is not);
                // of the DMA request enables only UDE is modelled.
                only(o, "DIER", v, 0xFF | dier::UDE.mask());
                self.dier = v;
            }
            off::SR => {
                // rc_w0 (§12.4.5): writing 0 clears a flag, writing 1 has no effect.
                self.tb.write_uif(v);
                for (c, ch) in self.ch.iter_mut().enumerate() {
                    if !sr::ccif(c as u32).on(v) {
                        ch.ccif = false;
                    }
                }
            }
            off::EGR => {
                only(o, "EGR (only UG is modelled)", v, egr::UG.mask());
                if egr::UG.on(v) {
                    self.ug();
                }
            }
            off::CCMR1 => self.write_ccmr1(o, v),
            off::CCMR2 => only(o, "CCMR2 (channels 3 and 4)", v, 0),
            off::CCER => self.write_ccer(o, v),
            off::CNT => {
                only(o, "CNT", v, 0xFFFF);
                self.tb.cnt = v;
                self.reeval();
            }
            off::PSC => {
                only(o, "PSC", v, 0xFFFF);
                self.tb.psc = v;
            }
            off::ARR => {
                only(o, "ARR", v, 0xFFFF);
                self.tb.write_arr(v);
                self.reeval();
            }
            off::RCR => {
                // REP[7:0]; REP_CNT only takes it at the next update event (§12.3.3).
                only(o, "RCR", v, dcr::REP.mask());
                self.rcr = v;
            }
            off::CCR1 | off::CCR2 => {
                only(o, "CCRx", v, 0xFFFF);
                let c = ((o - off::CCR1) / 4) as usize;
                self.ch[c].write_ccr(v, cnt, arr, pol);
                self.refresh_pins();
            }
            off::BDTR => {
                // OSSR and DTG only matter with complementary outputs (CCxNE = 1), which
                // the model refuses; break, AOE, OSSI and LOCK are not modelled.
                only(o, "BDTR", v, bdtr::MOE.mask() | bdtr::OSSR.mask() | bdtr::DTG.mask() | bdtr::BKP.mask());
                self.bdtr = v;
                self.refresh_pins();
            }
            off::DCR => {
                only(o, "DCR", v, dcr::DBA.mask() | dcr::DBL.mask());
                self.dcr = v;
                self.burst_idx = 0;
            }
            off::DMAR => {
                let (target, _) = self.dmar_target();
                self.write(target, v);
            }
            _ => unknown(o),
        }
    }

    fn write_cr1(&mut self, o: u32, v: u32) {
        if cr1::DIR.on(v) || cr1::CMS.get(v) != 0 {
            unmodelled("TIM1_CR1 (0x40010000): only edge-aligned up-counting is modelled (DIR = 0, CMS = 00)");
        }
        only(
            o,
            "CR1",
            v,
            cr1::CEN.mask() | cr1::UDIS.mask() | cr1::URS.mask() | cr1::OPM.mask() | cr1::ARPE.mask() | cr1::CKD.mask(),
        );
        self.tb.write_cr1(v);
        self.ckd = cr1::CKD.get(v);
        self.reeval();
    }

    fn write_cr2(&mut self, o: u32, v: u32) {
        let ois = (0..4).fold(0, |m, c| m | cr2::ois(c).mask()) | (0..3).fold(0, |m, c| m | cr2::oisn(c).mask());
        only(o, "CR2", v, cr2::MMS.mask() | cr2::CCDS.mask() | ois);
        if cr2::MMS.get(v) > cr2::MMS_OC2REF {
            unmodelled("TIM1_CR2.MMS (0x40010004): OC3REF/OC4REF as TRGO");
        }
        self.cr2 = v;
    }

    /// Channels 1 and 2's output compare modes and preload.
    fn write_ccmr1(&mut self, o: u32, v: u32) {
        let (cnt, arr, pol) = (self.tb.cnt, self.tb.arr_active, self.policy);
        let mut allowed = 0;
        for c in 0..2 {
            allowed |= ccmr::ocfe(c).mask() | ccmr::ocpe(c).mask() | ccmr::ocm(c).mask();
        }
        if ccmr::ccs(0).get(v) != 0 || ccmr::ccs(1).get(v) != 0 {
            unmodelled("TIM1_CCMR1.CCxS (0x40010018): input capture");
        }
        only(o, "CCMR1 (OCxCE is not modelled)", v, allowed);
        self.ccmr1_fe = v & (ccmr::ocfe(0).mask() | ccmr::ocfe(1).mask());
        for (c, ch) in self.ch.iter_mut().enumerate() {
            let c = c as u32;
            ch.set_preload(ccmr::ocpe(c).on(v), cnt, arr, pol);
            ch.set_mode(ccmr::ocm(c).get(v), cnt, arr, pol);
        }
        self.refresh_pins();
    }

    fn write_ccer(&mut self, o: u32, v: u32) {
        let mut allowed = 0;
        for c in 0..2 {
            allowed |= ccer::cce(c).mask() | ccer::ccp(c).mask() | ccer::ccnp(c).mask();
        }
        only(o, "CCER (complementary outputs and channels 3-4)", v, allowed);
        self.ccer = v;
        self.refresh_pins();
    }

    pub fn read(&mut self, o: u32) -> u32 {
        match o {
            off::CR1 => self.tb.cr1() | cr1::CKD.val(self.ckd),
            off::CR2 => self.cr2,
            off::SMCR | off::CCMR2 | off::EGR => 0,
            off::DIER => self.dier,
            off::SR => {
                let mut v = sr::UIF.val(self.tb.uif as u32);
                for (c, ch) in self.ch.iter().enumerate() {
                    v |= sr::ccif(c as u32).val(ch.ccif as u32);
                }
                v
            }
            off::CCMR1 => {
                let mut v = self.ccmr1_fe;
                for (c, ch) in self.ch.iter().enumerate() {
                    v |= ccmr::ocpe(c as u32).val(ch.preload as u32) | ccmr::ocm(c as u32).val(ch.mode);
                }
                v
            }
            off::CCER => self.ccer,
            off::CNT => self.tb.cnt,
            off::PSC => self.tb.psc,
            off::ARR => self.tb.arr,
            off::RCR => self.rcr,
            off::CCR1 => self.ch[0].ccr,
            off::CCR2 => self.ch[1].ccr,
            off::BDTR => self.bdtr,
            off::DCR => self.dcr,
            off::DMAR => {
                let (target, _) = self.dmar_target();
                self.read(target)
            }
            _ => unknown(o),
        }
    }
}
