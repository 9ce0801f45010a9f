//! TIM9, the two-channel general-purpose timer (RM0383 chapter 14, registers §14.4):
//! the up-counting time base (§14.3.1, §14.3.2 "Upcounting mode") on the internal
//! clock (§14.3.3, slave mode disabled) and channels 1 and 2 in output compare
//! (§14.3.7, §14.3.8). The registers are decoded in `tim9/regs.rs`, a channel is
//! `tim9/oc.rs`.
//!
//! Within the update event's cycle the shadows are loaded before the channels compare
//! CNT = 0 (as for TIM1 here): the manual does not say, and a program whose matches never
//! fall on CNT = 0 does not depend on it.

mod oc;
mod regs;

use crate::bits::ccer;
use crate::timebase::{Tick, TimeBase};
use oc::OcChannel;

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Tim9 {
    tb: TimeBase,
    ckd: u32,
    dier: u32,
    ch: [OcChannel; 2],
    /// CCMR1's OCxFE bits as written (no effect without a trigger input).
    ccmr1_fe: u32,
    ccer: u32,
    /// Update events so far (overflows and UG).
    pub updates: u64,
    /// Times UIF was set: what the TIM1_BRK_TIM9 interrupt would see with UIE = 1.
    pub uif_sets: u64,
    /// OC1/OC2 pin levels (PA2/PA3), and whether they changed since last taken.
    pub pins: [bool; 2],
    pub pins_dirty: bool,
}

impl Tim9 {
    pub fn new() -> Tim9 {
        Tim9 {
            tb: TimeBase::new(0xFFFF),
            ckd: 0,
            dier: 0,
            ch: [OcChannel::default(); 2],
            ccmr1_fe: 0,
            ccer: 0,
            updates: 0,
            uif_sets: 0,
            pins: [false; 2],
            pins_dirty: false,
        }
    }

    /// One CK_INT cycle: at an overflow the update event (unless UDIS), then both
    /// channels compare the new CNT (§14.3.2, §14.3.8).
    pub fn step(&mut self) {
        if !self.tb.latch_enable() {
            return;
        }
        match self.tb.clock() {
            Tick::Idle => {}
            Tick::Count => self.ticked(),
            Tick::Overflow => {
                if !self.tb.udis {
                    self.update_event(true);
                }
                self.ticked();
            }
        }
    }

    fn ticked(&mut self) {
        let cnt = self.tb.cnt;
        for ch in &mut self.ch {
            ch.tick(cnt);
        }
        self.refresh_pins();
    }

    /// The update event (§14.3.2 "When an update event occurs, all the registers are
    /// updated"): PSC and ARR shadows (§14.3.1), CCRx shadows with OCxPE (§14.4.6); UIF
    /// unless URS = 1 and the source is UG (§14.4.1 URS); OPM clears CEN (§14.4.1 OPM:
    /// "Counter stops counting at the next update event").
    fn update_event(&mut self, overflow: bool) {
        self.tb.load_shadows();
        for ch in &mut self.ch {
            ch.update_event();
        }
        self.updates += 1;
        if overflow || !self.tb.urs {
            self.tb.uif = true;
            self.uif_sets += 1;
        }
        if self.tb.opm {
            self.tb.stop();
        }
    }

    /// UG (§14.4.5): counter and prescaler counter re-initialised; an update event unless
    /// UDIS = 1. The re-initialisation is not a counter tick: no compare match.
    fn ug(&mut self) {
        if self.tb.ug() {
            self.update_event(false);
        }
    }

    /// OCx = OCxREF, inverted when CCxP = 1, while CCxE = 1 (§14.4.7: CC1E "1: On - OC1
    /// signal is output on the corresponding output pin", CC1P "0: OC1 active high, 1: OC1
    /// active low"); with CCxE = 0 the timer drives nothing and the pin reads low.
    fn refresh_pins(&mut self) {
        for (i, ch) in self.ch.iter().enumerate() {
            let c = i as u32;
            let level = ccer::cce(c).on(self.ccer) && (ch.oc_ref ^ ccer::ccp(c).on(self.ccer));
            if level != self.pins[i] {
                self.pins[i] = level;
                self.pins_dirty = true;
            }
        }
    }

    /// CK_INT cycles during which stepping changes nothing but CNT and the prescaler
    /// counter: up to the next overflow or compare match.
    pub fn quiet_cycles(&self) -> u64 {
        if !self.tb.enable_settled() {
            return 0;
        }
        if !self.tb.counting() {
            return u64::MAX;
        }
        let k = self.ch.iter().fold(self.tb.ticks_to_wrap(), |k, ch| k.min(self.tb.ticks_to_value(ch.ccr_active)));
        self.tb.pulses_before_tick(k)
    }

    /// Stopped: stepping changes nothing.
    pub fn idle(&self) -> bool {
        !self.tb.counting() && self.tb.enable_settled()
    }

    /// Skip `n` cycles known to be quiet.
    pub fn skip(&mut self, n: u64) {
        if self.tb.counting() {
            self.tb.skip_pulses(n);
        }
    }
}
