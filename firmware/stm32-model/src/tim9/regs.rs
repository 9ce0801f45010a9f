//! TIM9 register reads and writes (RM0383 §14.4). Bits the model does not implement
//! must stay at their reset value (0); anything else panics.

use super::Tim9;
use crate::addr::off;
use crate::bits::{ccer, ccmr, cr1, dier, egr, ocm, sr};
use crate::unmodelled;

#[track_caller]
fn only(o: u32, reg: &str, value: u32, allowed: u32) {
    crate::only_bits("TIM9", crate::addr::TIM9, o, reg, value, allowed);
}

impl Tim9 {
    pub fn write(&mut self, o: u32, v: u32) {
        match o {
            off::CR1 => {
                // TIM9_CR1 (§14.4.1): CKD, ARPE, OPM, URS, UDIS, CEN; bits 6:4 (DIR and
                // CMS on TIM1) are reserved: TIM9 only counts up.
                let allowed = [cr1::CEN, cr1::UDIS, cr1::URS, cr1::OPM, cr1::ARPE, cr1::CKD];
                only(o, "CR1", v, allowed.iter().fold(0, |m, f| m | f.mask()));
                self.tb.write_cr1(v);
                self.ckd = cr1::CKD.get(v);
            }
            // §14.4.2: SMS = 000, "the prescaler is clocked directly by the internal clock"
            // (§14.3.3); the slave mode controller is not modelled.
            off::SMCR => only(o, "SMCR (slave mode controller)", v, 0),
            off::DIER => {
                // §14.4.3: UIE, CC1IE, CC2IE, TIE, stored (interrupts are not delivered).
                only(o, "DIER", v, dier::UIE.mask() | dier::ccie(0).mask() | dier::ccie(1).mask() | dier::TIE.mask());
                self.dier = v;
            }
            off::SR => self.write_sr(v),
            off::EGR => {
                only(o, "EGR (only UG is modelled)", v, egr::UG.mask());
                if egr::UG.on(v) {
                    self.ug();
                }
            }
            off::CCMR1 => self.write_ccmr1(v),
            off::CCER => {
                // §14.4.7: "CC1NP ... CC1 channel configured as output: CC1NP must be kept
                // cleared"; the model only has outputs.
                let allowed = (0..2).fold(0, |m, c| m | ccer::cce(c).mask() | ccer::ccp(c).mask());
                only(o, "CCER (CCxNP must stay 0 for an output)", v, allowed);
                self.ccer = v;
                self.refresh_pins();
            }
            off::CNT => {
                only(o, "CNT", v, 0xFFFF);
                self.tb.cnt = v;
            }
            off::PSC => {
                only(o, "PSC", v, 0xFFFF);
                self.tb.psc = v;
            }
            off::ARR => {
                only(o, "ARR", v, 0xFFFF);
                self.tb.write_arr(v);
            }
            off::CCR1 | off::CCR2 => {
                only(o, "CCRx", v, 0xFFFF);
                self.ch[((o - off::CCR1) / 4) as usize].write_ccr(v);
            }
            // §14.4.13: no other register below 0x50; the model keeps those words at 0.
            o if o < off::OR => only(o, "register not implemented on TIM9 (must stay 0)", v, 0),
            _ => unknown(o),
        }
    }

    /// SR is rc_w0 (§14.4.4): writing 0 clears a flag, writing 1 has no effect.
    fn write_sr(&mut self, v: u32) {
        self.tb.write_uif(v);
        for (c, ch) in self.ch.iter_mut().enumerate() {
            if !sr::ccif(c as u32).on(v) {
                ch.ccif = false;
            }
        }
    }

    /// TIM9_CCMR1 in output mode (§14.4.6): OCxM, OCxPE, OCxFE; CCxS = 00 (output); bits 7
    /// and 15 reserved. PWM modes need the PWM comparison, which this model leaves out.
    fn write_ccmr1(&mut self, v: u32) {
        let o = off::CCMR1;
        if ccmr::ccs(0).get(v) != 0 || ccmr::ccs(1).get(v) != 0 {
            unmodelled("TIM9_CCMR1.CCxS (0x40014018): input capture");
        }
        let allowed = (0..2).fold(0, |m, c| m | ccmr::ocfe(c).mask() | ccmr::ocpe(c).mask() | ccmr::ocm(c).mask());
        only(o, "CCMR1", v, allowed);
        for c in 0..2 {
            if ccmr::ocm(c).get(v) >= ocm::PWM1 {
                unmodelled("TIM9_CCMR1.OCxM (0x40014018): PWM modes 1 and 2");
            }
        }
        self.ccmr1_fe = v & (ccmr::ocfe(0).mask() | ccmr::ocfe(1).mask());
        for (c, ch) in self.ch.iter_mut().enumerate() {
            ch.set_preload(ccmr::ocpe(c as u32).on(v));
            ch.set_mode(ccmr::ocm(c as u32).get(v));
        }
        self.refresh_pins();
    }

    pub fn read(&self, o: u32) -> u32 {
        match o {
            off::CR1 => self.tb.cr1() | cr1::CKD.val(self.ckd),
            off::SMCR | off::EGR => 0,
            off::DIER => self.dier,
            off::SR => self
                .ch
                .iter()
                .enumerate()
                .fold(sr::UIF.val(self.tb.uif as u32), |v, (c, ch)| v | sr::ccif(c as u32).val(ch.ccif as u32)),
            off::CCMR1 => self.ch.iter().enumerate().fold(self.ccmr1_fe, |v, (c, ch)| {
                v | ccmr::ocpe(c as u32).val(ch.preload as u32) | ccmr::ocm(c as u32).val(ch.mode)
            }),
            off::CCER => self.ccer,
            off::CNT => self.tb.cnt,
            off::PSC => self.tb.psc,
            off::ARR => self.tb.arr,
            off::CCR1 => self.ch[0].ccr,
            off::CCR2 => self.ch[1].ccr,
            _ => unknown(o),
        }
    }
}

fn unknown(o: u32) -> ! {
    unmodelled(&format!("TIM9 register at {:#010x}", crate::addr::TIM9 + o))
}
