//! TIM9's pins and update events as the tests see them.

use super::Mcu;

impl Mcu {
    /// PA2: TIM9_CH1 (OC1).
    pub fn pa2(&self) -> bool {
        self.pins[2]
    }
    /// PA3: TIM9_CH2 (OC2).
    pub fn pa3(&self) -> bool {
        self.pins[3]
    }
    /// TIM9 update events so far: every overflow (§14.3.2) and every UG (§14.4.5).
    pub fn tim9_updates(&self) -> u64 {
        self.tim9.updates
    }
    /// How many of those set TIM9's UIF (a UG with URS = 1 does not, §14.4.1): the
    /// update interrupts TIM1_BRK_TIM9 would take with UIE = 1.
    pub fn tim9_uif_sets(&self) -> u64 {
        self.tim9.uif_sets
    }
    /// The cycle in which TIM9 last set UIF (0 before it ever did).
    pub fn tim9_uif_at(&self) -> u64 {
        self.tim9_uif_at
    }

    /// Runs until TIM9 sets UIF once more (true; `cycle()` is then the cycle that set
    /// it) or until `limit` (false). The NVIC is not modelled: this is where a test
    /// starts its interrupt handler.
    pub fn run_to_tim9_update(&mut self, limit: u64) -> bool {
        let seen = self.tim9.uif_sets;
        while self.cycle < limit {
            let quiet = self.tim9.quiet_cycles().min(limit - self.cycle);
            if quiet > 0 {
                self.run_until(self.cycle + quiet);
            } else {
                self.step();
                if self.tim9.uif_sets != seen {
                    return true;
                }
            }
        }
        false
    }
}
