//! The lathe's position at a tick's instant from its last timed edge: the
//! edge's place (exact: `boundary_half_counts`) plus its age times the
//! speed between the last two timed edges. Between two counts the count
//! alone knows the position to ±½ count; an edge's time knows it to the
//! stamp's ±½ µs times the speed.
//!
//! The tick's instants are counted here (`stamps_per_tick` a tick), so the
//! latency with which the interrupt reads the registers never reaches the
//! position. Integer adds, multiplies and one 32-bit division per new edge
//! (no 64-bit division on the tick).

use super::track::{Clock, Track};
use super::{boundary_half_counts, EdgeClock, EdgeRegs, WRAP_Q8};
use crate::encoder::Extender;

/// How far past its count's interval the measurement may stand, Q16
/// counts: the count is read a little after the instant (1/32 count).
const SLACK_Q16: i64 = 1 << 11;
/// Timed edges from which the acceleration is taken: at least this many
/// stamps apart. Its error from the stamps' ±1 µs grows as 1/interval².
const RISE_ACCEL_MIN_STAMPS: i32 = 200;
/// The same for the count's changes, whose time is known only to the
/// tick (±½ tick): far slower crossings before the acceleration tells.
const COUNT_ACCEL_MIN_STAMPS: i32 = super::track::LATE_ACCEL;
/// The count's changes tell a speed only 10 ticks or more apart: their
/// times' ±½ tick is then at most 5 % of the interval. Closer, A rises
/// often enough to take over within a few ticks.
const CHANGE_MIN_TICKS: i32 = 10;

/// The registers as one word, to compare in one go (an `Option` of the
/// pair costs the tick twice the instructions), and no pair's word.
fn packed(r: &EdgeRegs) -> u64 {
    (r.count as u64) << 16 | r.stamp as u64
}
const NONE_YET: u64 = u64::MAX;

#[derive(Clone, Copy, Debug)]
pub struct EdgeTimer {
    clock: EdgeClock,
    /// this tick's instant, Q8 stamps, wrapping at 2^24 (before the first
    /// tick: a tick before `first_instant`)
    instant_q8: u32,
    /// A's rises, timed to the µs by the board
    rises: Track,
    /// the registers last followed, packed (`packed`; `NONE_YET` before)
    last_regs: u64,
    /// the count's changes, timed to the tick: what a lathe starting from
    /// rest gives before A has risen three times
    changes: Track,
    last_count: i64,
    /// the rises told last tick, and the changes were not followed
    changes_idle: bool,
    /// Q16 ticks a stamp (1/50 at 1 MHz and 20 kHz)
    ticks_per_stamp_q16: i32,
}

impl EdgeTimer {
    /// At low priority (it divides).
    pub fn new(clock: EdgeClock) -> EdgeTimer {
        let per_tick = clock.stamps_per_tick.max(1) as i64;
        let before_first = ((clock.first_instant as u32) << 8).wrapping_sub((clock.stamps_per_tick as u32) << 8);
        EdgeTimer {
            clock,
            instant_q8: before_first & WRAP_Q8,
            rises: Track::default(),
            last_regs: NONE_YET,
            changes: Track::default(),
            last_count: 0,
            changes_idle: false,
            ticks_per_stamp_q16: ((1 << 16) / per_tick) as i32,
        }
    }

    /// One tick: the registers the board latched, and the lathe's count as
    /// read this tick. Returns the measured position's offset from that
    /// count (Q16 counts), bounded to that count's interval (a stopped
    /// lathe is run on no further), or `None` where no crossing tells
    /// more than the count: before two with a speed they can give.
    #[inline]
    pub fn measure(&mut self, regs: Option<EdgeRegs>, lathe: &Extender) -> Option<i64> {
        let per_tick = self.clock.stamps_per_tick as i32;
        self.instant_q8 = self.instant_q8.wrapping_add((per_tick << 8) as u32) & WRAP_Q8;
        self.follow_rises(regs, lathe);
        let count = lathe.position();
        let at = match self.rises.position_q16() {
            // the rises tell: the count's changes wait (the tick's cost)
            Some(at) => {
                (self.last_count, self.changes_idle) = (count, true);
                at
            }
            None => {
                self.follow_changes(count);
                self.changes.position_q16()?
            }
        };
        let offset = at - (count << 16);
        Some(crate::q16::bound(offset, crate::q16::HALF + SLACK_Q16))
    }

    fn clock_for(&self, accel_min: i32, interval_min: i32) -> Clock {
        Clock {
            instant_q8: self.instant_q8,
            // (50 at 20 kHz: bounded, so that no product can overflow)
            per_tick: (self.clock.stamps_per_tick as i32).min(64),
            ticks_per_stamp_q16: self.ticks_per_stamp_q16,
            accel_min,
            // never 0: the interval divides
            interval_min: interval_min.max(1),
        }
    }

    /// A new rise: its place, and its time (the middle of its stamp: a
    /// stamp s holds the edges of [s, s + 1) µs).
    /// (Inlined: every tick calls it. Out of line, as the compiler left
    /// it, it cost the tick 11 instructions more on average when this was
    /// made, and 41 on the code as it stands now: counted on an emulated Cortex-M4.)
    #[inline(always)]
    fn follow_rises(&mut self, regs: Option<EdgeRegs>, lathe: &Extender) {
        let Some(r) = regs.filter(|r| packed(r) != self.last_regs) else {
            return self.rises.age();
        };
        self.last_regs = packed(&r);
        // the parity is the raw count's; positions start at 0 (raw ≡ pos + raw₀)
        let pos = lathe.position_of(r.count);
        let start_odd = (r.count as i64 - pos) & 1 == 1;
        let half = boundary_half_counts(pos, self.clock.low_low_odd ^ start_odd);
        let stamp_q8 = ((r.stamp as u32) << 8) + 128;
        self.rises.observe(half, stamp_q8, self.clock_for(RISE_ACCEL_MIN_STAMPS, 1));
    }

    /// A change of the count: the boundary it last crossed, in the middle
    /// of the tick it crossed in.
    fn follow_changes(&mut self, count: i64) {
        if self.changes_idle {
            // what they knew is old: start again from the next change
            (self.changes, self.changes_idle) = (Track::default(), false);
        }
        let per_tick = self.clock.stamps_per_tick as i32;
        let delta = count - self.last_count;
        self.last_count = count;
        if delta == 0 {
            return self.changes.age();
        }
        let half = 2 * count - delta.signum();
        let stamp_q8 = self.instant_q8.wrapping_sub((per_tick << 7) as u32) & WRAP_Q8;
        let interval_min = CHANGE_MIN_TICKS * self.clock.stamps_per_tick as i32;
        self.changes.observe(half, stamp_q8, self.clock_for(COUNT_ACCEL_MIN_STAMPS, interval_min));
    }
}

#[cfg(test)]
#[path = "timer_tests.rs"]
mod tests;
