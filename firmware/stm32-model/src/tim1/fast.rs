//! TIM1's part of `Mcu::run_until`'s fast path: how long nothing but the counter
//! changes, and how to jump over that stretch.

use super::Tim1;
use crate::bits::cr2;

impl Tim1 {
    /// CK_INT cycles during which stepping changes nothing but CNT and the prescaler
    /// counter: up to the next overflow or CCRx match (§12.3.9-10 act only there).
    pub fn quiet_cycles(&self) -> u64 {
        if !self.tb.enable_settled() || self.pending_uev || self.pending_ug {
            return 0;
        }
        if !self.tb.counting() {
            return u64::MAX;
        }
        let mut k = self.tb.ticks_to_wrap();
        for ch in &self.ch {
            k = k.min(self.tb.ticks_to_value(ch.ccr_active));
        }
        self.tb.pulses_before_tick(k)
    }

    /// Stopped with nothing pending: stepping changes nothing at all.
    pub fn idle(&self) -> bool {
        !self.tb.counting() && self.tb.enable_settled() && !self.pending_uev && !self.pending_ug && !self.dma_req
    }

    /// Skip `n` cycles known to be quiet.
    pub fn skip(&mut self, n: u64) {
        if self.tb.counting() {
            self.tb.skip_pulses(n);
        }
        self.trgo = self.quiet_trgo();
    }

    /// TRGO during quiet cycles: the level modes hold their level, pulses are low.
    pub fn quiet_trgo(&self) -> bool {
        match cr2::MMS.get(self.cr2) {
            cr2::MMS_ENABLE => self.tb.counting(),
            cr2::MMS_OC1REF => self.ch[0].oc_ref,
            cr2::MMS_OC2REF => self.ch[1].oc_ref,
            _ => false,
        }
    }
}
