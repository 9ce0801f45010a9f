//! One output-compare channel of TIM9: CCRx with its preload, OCxM and OCxREF, in the
//! modes that need no PWM comparison. RM0383 §14.3.7 (forced output mode), §14.3.8
//! (output compare mode), §14.4.6 (TIMx_CCMR1 OCxM/OCxPE), §14.4.4 (CCxIF).

use crate::bits::ocm;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct OcChannel {
    /// OCxM (3 bits): frozen, the three match modes or a forced level.
    pub mode: u32,
    /// OCxPE: "Preload register on TIMx_CCR1 enabled. Read/Write operations access the
    /// preload register. TIMx_CCR1 preload value is loaded in the active register at each
    /// update event" (§14.4.6).
    pub preload: bool,
    /// TIMx_CCRx as written (the preload register).
    pub ccr: u32,
    /// The active (shadow) register the counter is compared with.
    pub ccr_active: u32,
    /// OCxREF. Low at reset.
    pub oc_ref: bool,
    /// CCxIF.
    pub ccif: bool,
}

impl OcChannel {
    /// A counter tick left CNT at `cnt`. "When a match is found between the
    /// capture/compare register and the counter" the channel flag is set and OCxREF is
    /// driven as OCxM says (§14.3.8: "Assigns the corresponding output pin to a
    /// programmable value defined by the output compare mode ... Sets a flag in the
    /// interrupt status register (CCxIF)"); §14.4.6 OCxM: 001 "set channel 1 to active
    /// level on match", 010 "... inactive level on match", 011 "Toggle - OC1REF toggles
    /// when TIMx_CNT = TIMx_CCR1". Frozen (000) and the forced levels only set the flag.
    pub fn tick(&mut self, cnt: u32) {
        if cnt != self.ccr_active {
            return;
        }
        self.ccif = true;
        match self.mode {
            ocm::ACTIVE_ON_MATCH => self.oc_ref = true,
            ocm::INACTIVE_ON_MATCH => self.oc_ref = false,
            ocm::TOGGLE => self.oc_ref = !self.oc_ref,
            _ => {}
        }
    }

    /// OCxM written. The forced levels act at once: "OCxREF is forced low / high"
    /// (§14.4.6 OCxM = 100 / 101, §14.3.7 "Forced output mode"). Frozen and the match
    /// modes leave OCxREF where it is until their next match (the manual gives them no
    /// other effect).
    pub fn set_mode(&mut self, mode: u32) {
        self.mode = mode;
        match mode {
            ocm::FORCE_INACTIVE => self.oc_ref = false,
            ocm::FORCE_ACTIVE => self.oc_ref = true,
            _ => {}
        }
    }

    /// TIMx_CCRx written: with OCxPE = 0 "TIMx_CCR1 can be written at anytime, the new
    /// value is taken in account immediately" (§14.4.6).
    pub fn write_ccr(&mut self, value: u32) {
        self.ccr = value;
        if !self.preload {
            self.ccr_active = value;
        }
    }

    /// OCxPE written; clearing it makes the transfer permanent, as for ARPE (§14.3.1).
    pub fn set_preload(&mut self, preload: bool) {
        self.preload = preload;
        if !preload {
            self.ccr_active = self.ccr;
        }
    }

    /// Update event: the preload value is loaded in the active register (§14.4.6 OCxPE).
    pub fn update_event(&mut self) {
        if self.preload {
            self.ccr_active = self.ccr;
        }
    }
}
