//! One output-compare channel of TIM1: CCRx with its preload, OCxM and OCxREF.
//! RM0383 §12.3.8 (forced output), §12.3.9 (output compare), §12.3.10 (PWM mode),
//! §12.4.7 (CCMR1 OCxM/OCxPE).

use crate::bits::ocm;
use crate::PwmModeSwitch;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct OcChannel {
    /// OCxM (3 bits).
    pub mode: u32,
    /// OCxPE: "Preload register on TIMx_CCRx enabled ... the preload value is loaded in
    /// the active register at each update event" (§12.4.7).
    pub preload: bool,
    /// TIMx_CCRx as written (preload register).
    pub ccr: u32,
    /// The shadow register the counter is compared with.
    pub ccr_active: u32,
    /// OCxREF.
    pub oc_ref: bool,
    /// Last PWM comparison result, in PWM-mode-1 terms (true = "active").
    raw: bool,
    /// CCxIF.
    pub ccif: bool,
}

fn is_pwm(mode: u32) -> bool {
    mode == ocm::PWM1 || mode == ocm::PWM2
}

/// PWM mode 1 is active while the comparison holds, mode 2 is its inverse (§12.4.7).
fn pwm_level(mode: u32, raw: bool) -> bool {
    if mode == ocm::PWM1 {
        raw
    } else {
        !raw
    }
}

impl OcChannel {
    /// The PWM comparison in upcounting (§12.3.10 "PWM edge-aligned mode"): "OCxREF is
    /// high as long as TIMx_CNT < TIMx_CCRx else it becomes low. If the compare value in
    /// TIMx_CCRx is greater than the auto-reload value (in TIMx_ARR) then OCxREF is held
    /// at '1'. If the compare value is 0 then OCxRef is held at '0'" (PWM mode 1 terms).
    fn compare(&self, cnt: u32, arr: u32) -> bool {
        if self.ccr_active > arr {
            true
        } else {
            cnt < self.ccr_active
        }
    }

    /// A counter tick left CNT at `cnt`. A match (CNT = CCRx shadow) sets CCxIF in every
    /// mode (§12.4.5 CC1IF) and drives OCxREF in the match modes (§12.3.9, §12.4.7:
    /// active on match, inactive on match, toggle). Returns whether it matched.
    pub fn tick(&mut self, cnt: u32, arr: u32, policy: PwmModeSwitch) -> bool {
        let matched = cnt == self.ccr_active;
        if matched {
            self.ccif = true;
            match self.mode {
                ocm::ACTIVE_ON_MATCH => self.oc_ref = true,
                ocm::INACTIVE_ON_MATCH => self.oc_ref = false,
                ocm::TOGGLE => self.oc_ref = !self.oc_ref,
                _ => {}
            }
        }
        self.reeval(cnt, arr, policy);
        matched
    }

    /// Something other than a counter tick changed CNT, CCRx shadow or ARR shadow: in PWM
    /// mode "TIMx_CNT and TIMx_CCRx are always compared" (§12.3.10), so OCxREF follows
    /// the new comparison result. Match modes only act on counter ticks (assumption).
    pub fn reeval(&mut self, cnt: u32, arr: u32, policy: PwmModeSwitch) {
        let raw = self.compare(cnt, arr);
        if is_pwm(self.mode) && (policy == PwmModeSwitch::Reevaluate || raw != self.raw) {
            self.oc_ref = pwm_level(self.mode, raw);
        }
        self.raw = raw;
    }

    /// OCxM written. Forced modes act at once: "OCxREF is forced low/high" (§12.4.7,
    /// §12.3.8 "Forced output mode"). Entering a PWM mode re-evaluates REF, either
    /// always or only from frozen, as `policy` says (see [`PwmModeSwitch`]). Frozen and
    /// the match modes leave REF where it was until their next event.
    pub fn set_mode(&mut self, mode: u32, cnt: u32, arr: u32, policy: PwmModeSwitch) {
        let old = self.mode;
        self.mode = mode;
        let raw = self.compare(cnt, arr);
        match mode {
            ocm::FORCE_INACTIVE => self.oc_ref = false,
            ocm::FORCE_ACTIVE => self.oc_ref = true,
            ocm::PWM1 | ocm::PWM2 if policy == PwmModeSwitch::Reevaluate || old == ocm::FROZEN => {
                self.oc_ref = pwm_level(mode, raw)
            }
            _ => {}
        }
        self.raw = raw;
    }

    /// TIMx_CCRx written: "OC1PE = 0: TIMx_CCR1 can be written at anytime, the new value is
    /// taken in account immediately" (§12.4.7).
    pub fn write_ccr(&mut self, value: u32, cnt: u32, arr: u32, policy: PwmModeSwitch) {
        self.ccr = value;
        if !self.preload {
            self.ccr_active = value;
            self.reeval(cnt, arr, policy);
        }
    }

    /// OCxPE written; clearing it makes the transfer permanent, as for ARPE (§12.3.1).
    pub fn set_preload(&mut self, preload: bool, cnt: u32, arr: u32, policy: PwmModeSwitch) {
        self.preload = preload;
        if !preload && self.ccr_active != self.ccr {
            self.ccr_active = self.ccr;
            self.reeval(cnt, arr, policy);
        }
    }

    /// Update event: "the preload value is loaded in the active register at each update
    /// event" when OCxPE = 1 (§12.4.7). The caller re-evaluates REF afterwards.
    pub fn update_event(&mut self) {
        if self.preload {
            self.ccr_active = self.ccr;
        }
    }
}
