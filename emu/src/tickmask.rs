//! Thread-mode sections that hold off the tick: BASEPRI raised to the tick's
//! level or above (the tick's own lock, `app/tick/shared.rs`'s `locked`), or PRIMASK.
//! The E-stop, one level above the tick, is held off only by PRIMASK
//! (`machine/primask.rs`); this is what can delay the tick itself.
//!
//! BASEPRI masks priorities numerically at or above its value when non-zero
//! (PM0214 §2.1.3); BASEPRI_MAX only ever raises it (writes a value that is
//! non-zero and more urgent than the current one, or anything over 0).

use crate::chip::probe::TICK_PRIO;
use crate::chip::Chip;
use unicorn_engine::{RegisterARM as R, Unicorn};

/// BASEPRI after an `msr` to BASEPRI (`max` false) or BASEPRI_MAX of `value`.
pub fn next_basepri(current: u32, value: u32, max: bool) -> u32 {
    let v = value & 0xFF;
    if !max || (v != 0 && (current == 0 || v < current)) {
        v
    } else {
        current
    }
}

/// True when these mask the tick.
pub fn masks_tick(primask: bool, basepri: u32) -> bool {
    // the NVIC implements the top 4 bits (PM0214 §4.3.7)
    let basepri = basepri & 0xF0;
    primask || (basepri != 0 && basepri <= TICK_PRIO)
}

/// Before an instruction at `addr` (at `t` on both clocks, in thread mode)
/// sets PRIMASK and BASEPRI to these: opens or closes a section.
pub fn change(uc: &mut Unicorn<Chip>, t: (u64, u64), addr: u32, primask: bool, basepri: u32) {
    if uc.reg_read(R::IPSR).unwrap_or(0) & 0x1FF != 0 {
        return;
    }
    let was = masks_tick(uc.reg_read(R::PRIMASK).unwrap_or(0) & 1 == 1, uc.reg_read(R::BASEPRI).unwrap_or(0) as u32);
    let now = masks_tick(primask, basepri);
    let lr = uc.reg_read(R::LR).unwrap_or(0) as u32 & !1;
    let c = uc.get_data_mut();
    let tick_on = c.nvic.enabled[crate::svd::irq(polyturn_firmware::board::TICK_IRQ)];
    match (was, now) {
        (false, true) => {
            c.tickmask.open(t, (addr, lr), tick_on);
            // the bound's cache is cold as the section starts: anything may
            // have run just before
            c.meter.cold();
        }
        (true, false) => c.tickmask.close(t),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chip::probe::PLAN_PRIO;

    #[test]
    fn basepri_max_only_raises_and_basepri_writes_anything() {
        assert_eq!(next_basepri(0, 0x10, true), 0x10);
        assert_eq!(next_basepri(0x20, 0x10, true), 0x10, "more urgent: raised");
        assert_eq!(next_basepri(0x10, 0x20, true), 0x10, "less urgent: kept");
        assert_eq!(next_basepri(0x10, 0, true), 0x10, "0 through BASEPRI_MAX: no effect");
        assert_eq!(next_basepri(0x10, 0, false), 0, "BASEPRI: restored");
    }

    #[test]
    fn the_ticks_lock_masks_it_and_the_global_section_does_not() {
        assert!(masks_tick(false, TICK_PRIO));
        assert!(!masks_tick(false, PLAN_PRIO), "the step plan's level, one lower");
        assert!(!masks_tick(false, PLAN_PRIO + 0x10), "cs.rs's mask, below the plan's");
        assert!(!masks_tick(false, 0), "0 masks nothing");
        assert!(masks_tick(true, 0));
    }
}
