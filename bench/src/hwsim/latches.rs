//! The lathe encoder's edge latches for the sweep's lathe: what TIM3_CCR1
//! and TIM5_CCR3 hold when the tick reads them (`polyturn_sync::edges`).
//! The sweep's lathe is a count function x(t) read as ⌊x⌋, so count c
//! holds [c, c + 1) and, with the count 0 in state (A,B) = (0,0), A rises
//! at x ≡ 1 (mod 4) counting up and at x ≡ 3 counting down (RM0383 Table
//! 53's cycle).

use super::{TICK_LEN, TIMER_HZ};
use polyturn_sync::edges::{EdgeClock, EdgeRegs};

/// Timer cycles per stamp (TIM5 at 1 MHz).
const CYCLES_PER_STAMP: u64 = TIMER_HZ as u64 / 1_000_000;
/// The stamp at the first tick's instant: not 0, so runs cross its wrap.
const FIRST_STAMP: u64 = 65_000;

/// Follows x(t) from read to read and keeps A's last rise.
pub struct Latches {
    /// the rig's first tick instant, cycles
    start: u64,
    last_read: u64,
    regs: Option<EdgeRegs>,
}

impl Latches {
    pub fn new(first_tick: u64) -> Latches {
        Latches { start: first_tick, last_read: first_tick, regs: None }
    }

    /// The core's edge clock for the rig's ticks.
    pub fn clock() -> EdgeClock {
        let per_tick = (TICK_LEN as u64 / CYCLES_PER_STAMP) as u16;
        EdgeClock { first_instant: FIRST_STAMP as u16, stamps_per_tick: per_tick, low_low_odd: false }
    }

    /// The registers at `read_at` (cycles), the lathe at `x(seconds)`.
    pub fn read(&mut self, x: &dyn Fn(f64) -> f64, read_at: u64) -> Option<EdgeRegs> {
        let secs = |c: u64| c as f64 / TIMER_HZ as f64;
        let (t0, t1) = (self.last_read.max(self.start), read_at);
        self.last_read = read_at;
        let (x0, x1) = (x(secs(t0)), x(secs(t1)));
        if x0.floor() == x1.floor() {
            return self.regs;
        }
        let up = x1 > x0;
        // the last boundary crossed the way A rises: up at 1 (mod 4), down at 3
        let b = if up { ((x1 - 1.0) / 4.0).floor() * 4.0 + 1.0 } else { ((x1 - 3.0) / 4.0).ceil() * 4.0 + 3.0 };
        if (up && b <= x0.floor()) || (!up && b > x0.floor()) {
            return self.regs;
        }
        let at = crossing(x, t0, t1, b, up);
        let stamp = FIRST_STAMP + at.saturating_sub(self.start) / CYCLES_PER_STAMP;
        let count = if up { b } else { b - 1.0 };
        self.regs = Some(EdgeRegs { count: count as i64 as u16, stamp: stamp as u16 });
        self.regs
    }
}

/// The cycle at which x crosses `b` between `lo` and `hi` (bisection: the
/// lathe moves one way within a tick).
fn crossing(x: &dyn Fn(f64) -> f64, mut lo: u64, mut hi: u64, b: f64, up: bool) -> u64 {
    let secs = |c: u64| c as f64 / TIMER_HZ as f64;
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if (x(secs(mid)) >= b) == up {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}
