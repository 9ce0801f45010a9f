//! The interrupt lines into the NVIC (RM0383 §10.1.3 table 37, the vector table). Each is a level:
//! a timer's is SR & DIER (§12.4.4, §13.4.4), EXTI's PR & IMR (§10.3). Some vectors
//! are shared: TIM1's update with TIM10, its trigger/commutation with TIM11, its
//! break with TIM9; EXTI lines 5-9 and 10-15.

use super::Chip;
use crate::svd;
use polyturn_stm32_model::addr::{off, TIM1, TIM11, TIM2, TIM9};
use std::sync::OnceLock;

/// The lines `Chip::levels` reads, in its order, by their SVD names.
const LINES: [&str; 16] = [
    "TIM1_UP_TIM10",
    "TIM1_TRG_COM_TIM11",
    "TIM1_BRK_TIM9",
    "TIM1_CC",
    "TIM2",
    "TIM3",
    "TIM4",
    "TIM5",
    "EXTI0",
    "EXTI1",
    "EXTI2",
    "EXTI3",
    "EXTI4",
    "EXTI9_5",
    "EXTI15_10",
    "OTG_FS",
];

/// `LINES`' IRQ numbers, looked up in the SVD once (every bus access asks).
fn numbers() -> &'static [usize; 16] {
    static N: OnceLock<[usize; 16]> = OnceLock::new();
    N.get_or_init(|| LINES.map(svd::irq))
}

impl Chip {
    fn mcu_flags(&mut self, base: u32) -> u32 {
        self.mcu.read(base + off::SR) & self.mcu.read(base + off::DIER)
    }

    /// Each line of `LINES`, asserted or not, now.
    fn levels(&mut self) -> [bool; 16] {
        // SR's overcapture flags (bits 9-12) sit under DIER's DMA enables: only the
        // interrupt flags count (UIF, CCxIF, TIF: §13.4.4/§13.4.5, §14.4.4/§14.4.5)
        let t2 = self.mcu_flags(TIM2) & 0x5F;
        let (t1, t9, t11) = (self.mcu_flags(TIM1), self.mcu_flags(TIM9) & 0x47, self.mcu_flags(TIM11) & 0x03);
        let gp = |c: &Chip, i: usize| c.gp[i].irq(0xFF);
        [
            t1 & 0x01 != 0 || gp(self, 3),
            t1 & 0x60 != 0 || t11 != 0,
            t1 & 0x80 != 0 || t9 != 0,
            t1 & 0x1E != 0,
            t2 != 0,
            gp(self, 0),
            gp(self, 1),
            gp(self, 2),
            self.exti.pending(0, 0),
            self.exti.pending(1, 1),
            self.exti.pending(2, 2),
            self.exti.pending(3, 3),
            self.exti.pending(4, 4),
            self.exti.pending(5, 9),
            self.exti.pending(10, 15),
            self.usb.irq(),
        ]
    }

    /// PM0214 §4.3.9: a level-sensitive line that is asserted while its interrupt is
    /// not active sets the pending bit (and again after return if still asserted).
    pub fn update_lines(&mut self) {
        let n = numbers();
        for (_, &irq) in self.levels().iter().zip(n).filter(|l| *l.0) {
            if !self.active.contains(&(16 + irq)) {
                self.nvic.pending[16 + irq] = true;
            }
        }
    }

    /// The execution priority (PM0214 §2.1.3, §2.3.6): the highest (lowest value)
    /// group priority among active exceptions, boosted to 0 by PRIMASK and to its
    /// value by BASEPRI; 256 with nothing active.
    pub fn exec_priority(&self, primask: bool, basepri: u32) -> u32 {
        let mut p = self.active.iter().map(|&e| self.nvic.group(self.nvic.prio[e])).min().unwrap_or(256);
        if primask {
            p = 0;
        }
        let bp = basepri & 0xF0;
        if bp != 0 {
            p = p.min(self.nvic.group(bp as u8));
        }
        p
    }

    /// The pending exception that pre-empts now, if any (strictly higher priority).
    pub fn deliverable(&self, primask: bool, basepri: u32) -> Option<usize> {
        let e = self.nvic.best_pending()?;
        // a job's hold: as if BASEPRI stood at the tick's level (the tick's
        // own lock, `app/tick/shared.rs`), or at the plan's (the tick unmasked),
        // unless something masks more already
        let bp = basepri & 0xF0;
        let hold = if self.now < self.tick_held_until {
            crate::chip::probe::TICK_PRIO
        } else if self.now < self.plan_held_until {
            crate::chip::probe::PLAN_PRIO
        } else {
            0
        };
        let held = hold != 0 && (bp == 0 || bp > hold);
        let basepri = if held { hold } else { basepri };
        (self.nvic.group(self.nvic.prio[e]) < self.exec_priority(primask, basepri)).then_some(e)
    }
}

#[cfg(test)]
mod tests {
    use crate::chip::Chip;
    use polyturn_stm32_model::Params;

    /// A job's hold keeps the pending tick out exactly as BASEPRI at the
    /// tick's level would, until its cycle, and leaves a more urgent mask
    /// (PRIMASK) as it is.
    #[test]
    fn a_hold_keeps_the_pending_tick_out_until_its_end() {
        let mut c = Chip::new(Params::default());
        let tick = crate::chip::probe::tick_exc();
        c.nvic.prio[tick] = crate::chip::probe::TICK_PRIO as u8;
        (c.nvic.pending[tick], c.nvic.enabled[tick - 16]) = (true, true);
        assert_eq!(c.deliverable(false, 0), Some(tick), "unheld: taken");
        c.tick_held_until = c.now + 100;
        assert_eq!(c.deliverable(false, 0), None, "held");
        assert_eq!(c.deliverable(false, crate::chip::probe::TICK_PRIO), None, "held, and its lock taken too");
        assert_eq!(c.deliverable(true, 0), None, "PRIMASK");
        c.now += 100;
        assert_eq!(c.deliverable(false, 0), Some(tick), "the hold is over");
    }

    /// A hold on the plan's level keeps the pending plan out, not the tick.
    #[test]
    fn a_plan_hold_keeps_the_plan_out_and_lets_the_tick_in() {
        let mut c = Chip::new(Params::default());
        let (tick, plan) = (crate::chip::probe::tick_exc(), crate::chip::probe::plan_exc());
        c.nvic.prio[tick] = crate::chip::probe::TICK_PRIO as u8;
        c.nvic.prio[plan] = crate::chip::probe::PLAN_PRIO as u8;
        (c.nvic.pending[plan], c.nvic.enabled[plan - 16]) = (true, true);
        assert_eq!(c.deliverable(false, 0), Some(plan), "unheld: taken");
        c.plan_held_until = c.now + 100;
        assert_eq!(c.deliverable(false, 0), None, "held");
        (c.nvic.pending[tick], c.nvic.enabled[tick - 16]) = (true, true);
        assert_eq!(c.deliverable(false, 0), Some(tick), "the tick is not held");
        c.nvic.pending[tick] = false;
        c.now += 100;
        assert_eq!(c.deliverable(false, 0), Some(plan), "the hold is over");
    }
}
