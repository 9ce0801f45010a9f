//! The timer's inputs: TI1 and TI2 counted by the encoder interface (§13.3.12), input
//! capture on TI1..TI3 and on TRC (§13.3.5), and the trigger output's compare pulse
//! (§13.4.2 MMS = 011), which is how TIM3's channel 1 reaches TIM5 ([`super::trigger`]).

use super::GpTimer;
use crate::addr::off::{CCER, CCMR1, CCMR2, CCR1, CR1, CR2, SMCR, SR};
use crate::bits::{ccer, ccmr, ccmr_in, cr2, smcr};
use crate::encoder::{table_53, Count, Counting};
use crate::EncoderCapture;

impl GpTimer {
    /// New levels of TI1, TI2 (the encoder's A and B) and TI3 (the index). In encoder
    /// mode a change of TI1 or TI2 counts as table 53 says for SMS (§13.4.3: 001
    /// counts on TI1 edges, 010 on TI2's, 011 on both; §13.3.12's text swaps the first
    /// two, so only 011 is relied on) and sets CR1.DIR (§13.4.1). A rising edge of TIx
    /// captures on channel x while it takes TIx (`capture_on`); where the same edge is
    /// counted, the capture latches CNT before or after that count as
    /// [`EncoderCapture`] says (the manual does not).
    pub fn inputs(&mut self, ti: [bool; 3]) {
        for (i, &level) in ti.iter().enumerate().take(2) {
            if level == self.ti[i] {
                continue;
            }
            self.ti[i] = level;
            let capture = level && self.capture_on(i, ccmr_in::CCS_TI);
            if capture && self.encoder_capture == EncoderCapture::CountBefore {
                self.capture(i);
            }
            self.encoder_edge(i, level);
            if capture && self.encoder_capture == EncoderCapture::CountAfter {
                self.capture(i);
            }
        }
        if ti[2] && !self.ti[2] && self.capture_on(2, ccmr_in::CCS_TI) {
            self.capture(2);
        }
        self.ti[2] = ti[2];
    }

    /// TI1 or TI2 (`i` = 0, 1) changed to `level`: the encoder interface's count.
    fn encoder_edge(&mut self, i: usize, level: bool) {
        let counting = match smcr::SMS.get(self.regs.get(SMCR)) {
            1 => Counting::Ti1Only,
            2 => Counting::Ti2Only,
            3 => Counting::Both,
            _ => return,
        };
        let (col, opposite) = (2 * i + !level as usize, self.ti[1 - i]);
        let dir_down = table_53(Counting::Both, opposite)[col] == Count::Down;
        self.regs.set(CR1, self.regs.get(CR1) & !0x10 | (dir_down as u32) << 4);
        match table_53(counting, opposite)[col] {
            Count::Up => self.count_by(1),
            Count::Down => self.count_by(-1),
            Count::None => {}
        }
    }

    /// Channel `ch` captures rising edges of the input `ccs` selects: CCxS = `ccs`
    /// (§13.4.7: 01 ICx on TIx, 11 on TRC), CCxE = 1 ("capture enabled", §13.4.9),
    /// CCxP = CCxNP = 0 (rising edge) and ICxPSC = 00 ("capture is done each time an
    /// edge is detected"). Other polarities and prescalers are not modelled: no capture.
    pub(super) fn capture_on(&self, ch: usize, ccs: u32) -> bool {
        if ch >= self.channels {
            return false;
        }
        let (ccmr, c, e) = (if ch < 2 { CCMR1 } else { CCMR2 }, (ch % 2) as u32, self.regs.get(CCER));
        let m = self.regs.get(ccmr);
        let n = ch as u32;
        ccmr::ccs(c).get(m) == ccs
            && ccmr_in::icpsc(c).get(m) == 0
            && ccer::cce(n).on(e)
            && !ccer::ccp(n).on(e)
            && !ccer::ccnp(n).on(e)
    }

    /// §13.3.5: "the TIMx_CCR1 register gets the value of the counter on the active
    /// transition. CC1IF flag is set ... CC1OF is also set if at least two
    /// consecutive captures occurred whereas the flag was not cleared" (channel x:
    /// CCRx, CCxIF at bit x, CCxOF at bit 8 + x).
    pub(super) fn capture(&mut self, ch: usize) {
        self.regs.set(CCR1 + 4 * ch as u32, self.cnt);
        let (sr, flag) = (self.regs.get(SR), 2 << ch);
        self.regs.set(SR, sr | flag | (sr & flag) << 8);
        if ch == 0 {
            self.cc1_event();
        }
    }

    /// §13.4.2 MMS = 011 "Compare Pulse - The trigger output send a positive pulse when
    /// the CC1IF flag is to be set (even if it was already high), as soon as a capture
    /// or a compare match occurred".
    pub(super) fn cc1_event(&mut self) {
        if cr2::MMS.get(self.regs.get(CR2)) == cr2::MMS_COMPARE_PULSE {
            self.trgo += 1;
        }
    }

    /// The TRGO pulses made since the last call, for the timers whose trigger input
    /// this timer's TRGO is ([`super::trigger`]).
    pub fn take_trgo(&mut self) -> u32 {
        std::mem::take(&mut self.trgo)
    }

    /// A pulse on internal trigger input ITRx (`itr` 0..=3). With TS selecting it
    /// (§13.4.3: "000: Internal Trigger 0 (ITR0) ... 011: Internal Trigger 3"), it is
    /// TRGI, and TRC with it (the block diagram, §13.2: TRC comes from ITR0..3 and
    /// TI1F_ED through the trigger selection): each channel with CCxS = 11 ("IC1 is
    /// mapped on TRC. This mode is working only if an internal trigger input is
    /// selected through TS bit") captures CNT at the pulse's rising edge. TRGI does
    /// nothing else here: SMS = 000 ("slave mode disabled") is the only non-encoder
    /// slave mode modelled, and the resynchronisation of the pulse (a few CK_INT
    /// cycles) is not.
    pub fn trigger(&mut self, itr: u32) {
        if smcr::TS.get(self.regs.get(SMCR)) != itr || itr > 3 {
            return;
        }
        for ch in 0..self.channels {
            if self.capture_on(ch, ccmr_in::CCS_TRC) {
                self.capture(ch);
            }
        }
    }
}

#[cfg(test)]
mod tests;
