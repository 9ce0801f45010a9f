//! The machine behind the fake board (tests): time passes between the
//! host's commands, the lathe turns at a set speed with an index every
//! `cpr` counts, and the step output emits what each tick planned two
//! ticks later (`steps::pipe`), so jogs and the encoder check really run.

use polyturn_sync::{Controller, TickInput};

pub struct Machine {
    /// control ticks that pass before each command line is handled
    pub ticks_per_line: usize,
    /// lathe speed, counts per tick (hand turning: a fraction of one)
    pub counts_per_tick_x1000: i64,
    /// the encoder's real counts per turn (its index comes once a turn)
    pub cpr: i64,
    /// the machinist's hand on the chuck: before the line that ends an
    /// encoder check, the lathe rests 1.2 s and then turns at
    /// `counts_per_tick_x1000`; at any other time it rests
    pub turn_for_check: bool,
    lathe_milli: i64,
    emitted: u16,
    pipe: [u16; 2],
    t: usize,
}

impl Machine {
    pub fn new(ticks_per_line: usize) -> Machine {
        Machine {
            ticks_per_line,
            counts_per_tick_x1000: 0,
            cpr: 2400,
            turn_for_check: false,
            lathe_milli: 0,
            emitted: 0,
            pipe: [0; 2],
            t: 0,
        }
    }

    pub fn run(&mut self, ctl: &mut Controller, line: &str) {
        let checking = self.turn_for_check && line.contains("check-encoder stop");
        for i in 0..self.ticks_per_line {
            let before = self.lathe_milli / 1000;
            let turning = !self.turn_for_check || (checking && i >= 30_000);
            if turning {
                self.lathe_milli += self.counts_per_tick_x1000;
            }
            let now = self.lathe_milli / 1000;
            // the index at count 5 of every turn, latched as it passes
            let index = (before.min(now) + 1..=before.max(now)).find(|c| c.rem_euclid(self.cpr) == 5).map(|c| c as u16);
            let out = ctl.tick(&TickInput { lathe: now as u16, index, emitted: self.emitted, ..TickInput::default() });
            self.emitted = self.emitted.wrapping_add(self.pipe[self.t % 2]);
            self.pipe[self.t % 2] = out.plan.count;
            self.t += 1;
            if self.t.is_multiple_of(25) {
                ctl.service();
            }
        }
    }
}
