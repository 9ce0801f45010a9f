//! A bench for the controller's tests: a lathe that turns at a set speed
//! and a step output that does what it is told (each plan's pulses counted
//! two ticks later, `steps::pipe`; nothing more once it is halted), and an
//! X output that emits each plan within its tick, if asked to.

use super::{Controller, TickInput, TickOutput};
use crate::config::Config;
use crate::steps::Dir;
use crate::timing::Timing;

pub(super) struct Rig {
    pub c: Controller,
    /// the lathe's position, Q16 counts
    pub lathe_q16: i64,
    /// the step output's pulse counter and the two plans in flight
    pub emitted: u16,
    pipe: [u16; 2],
    t: usize,
    /// the X output's pulse counter; `x_emits` says whether it emits
    pub x_emitted: u16,
    pub x_emits: bool,
    /// net cutter steps the output made (signed by DIR)
    pub cutter_net: i64,
    dirs: [Dir; 2],
}

impl Rig {
    pub fn new(config: Config) -> Rig {
        let mut c = Controller::new(config, Timing::FIRMWARE);
        c.start(0, 0, 0);
        Rig {
            c,
            lathe_q16: 0,
            emitted: 0,
            pipe: [0; 2],
            t: 0,
            x_emitted: 0,
            x_emits: true,
            cutter_net: 0,
            dirs: [Dir::Forward; 2],
        }
    }

    /// The lathe's position in whole counts.
    pub fn lathe(&self) -> i64 {
        self.lathe_q16 >> 16
    }

    /// One tick with the lathe moved by `speed_q16` (Q16 counts) first.
    pub fn tick(&mut self, speed_q16: i64) -> TickOutput {
        self.tick_with(speed_q16, TickInput::default())
    }

    /// One tick; `io`'s counters are filled in from the bench.
    pub fn tick_with(&mut self, speed_q16: i64, io: TickInput) -> TickOutput {
        self.lathe_q16 += speed_q16;
        let io = TickInput { lathe: self.lathe() as u16, emitted: self.emitted, x_emitted: self.x_emitted, ..io };
        let out = self.c.tick(&io);
        // the window planned two ticks ago runs now (unless halted)
        let slot = self.t % 2;
        let n = if out.halt { 0 } else { self.pipe[slot] };
        self.emitted = self.emitted.wrapping_add(n);
        self.cutter_net += if self.dirs[slot] == Dir::Forward { n as i64 } else { -(n as i64) };
        if out.halt {
            self.pipe = [0; 2];
        }
        self.pipe[slot] = out.plan.count;
        self.dirs[slot] = out.plan.dir;
        self.t += 1;
        if self.x_emits {
            self.x_emitted = self.x_emitted.wrapping_add(out.x_plan.count);
        }
        out
    }

    /// `n` ticks at `speed_q16`; panics on any fault.
    pub fn run(&mut self, speed_q16: i64, n: usize) {
        for k in 0..n {
            self.tick(speed_q16);
            assert_eq!(self.c.fault(), None, "tick {k}: {:?}", self.c.state());
        }
    }

    /// Ticks at `speed_q16` until `done` holds (at most `limit` ticks);
    /// returns how many it took.
    pub fn until(&mut self, speed_q16: i64, limit: usize, done: impl Fn(&Controller) -> bool) -> usize {
        for k in 0..limit {
            if done(&self.c) {
                return k;
            }
            self.tick(speed_q16);
        }
        panic!("not done in {limit} ticks: {:?}", self.c.state());
    }
}

/// The board's X axis (`cam_upload::X_MAX_RATE_HZ`, one step per two
/// ticks) at `accel` steps/s², at the board's tick.
pub(super) fn x_limits(accel: u64) -> crate::follower::Limits {
    let tick_hz = Timing::FIRMWARE.tick_hz as u64;
    crate::follower::Limits::from_rates(crate::cam_upload::X_MAX_RATE_HZ as u64, accel, tick_hz)
}

/// Q16 counts per tick.
pub(super) const fn per_tick(counts: f64) -> i64 {
    (counts * 65536.0) as i64
}
