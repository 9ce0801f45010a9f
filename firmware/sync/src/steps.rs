//! Step scheduling for a stepper (or a servo taking step/dir): per tick, how
//! many steps to emit in the next tick, when the first one falls and the
//! period between them, so steps are evenly spaced *across* tick boundaries
//! (each step sits where the commanded position crosses a half step, as in
//! Klipper's stepcompress and Didge's evenly spaced steps).
//!
//! Each step rises within half a timer tick of its exact instant, at least
//! a pulse high and a pulse low after the step before (across ticks too),
//! and after a reversal DIR's setup time after DIR turned (`Prev`). The
//! X axis, stepped from the tick, closes on the steps it really emitted
//! (`book::StepBook`); the cutter's hardware-timed output runs each plan
//! two ticks later and its books check the pulse count (`pipe`).

/// Which way DIR points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Dir {
    #[default]
    Forward,
    Reverse,
}

/// What the step generator emits during the next tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StepPlan {
    pub count: u16,
    pub dir: Dir,
    /// timer ticks from the start of the tick to the first step (whole part)
    pub first: u32,
    /// timer ticks between steps (whole part)
    pub period: u32,
    /// the fractions of `first` and `period`, in 1/256 of a timer tick
    pub first_frac: u8,
    pub frac: u8,
}

impl StepPlan {
    /// Timer ticks from the start of the tick to step `i` (from 0): each
    /// step rounded to the nearest tick of the exact, evenly spaced train.
    #[inline]
    pub fn at(&self, i: u32) -> u32 {
        let period_q8 = (self.period << 8) + self.frac as u32;
        self.first + ((self.first_frac as u32 + i * period_q8 + 128) >> 8)
    }
}

/// Timing constants of the step generator, in its timer's ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepTiming {
    /// timer ticks per control tick
    pub tick_len: u32,
    /// shortest allowed period (pulse high + low), at least 2 × `pulse`
    pub min_period: u32,
    /// DIR to first STEP setup time
    pub dir_setup: u32,
    /// STEP pulse high time
    pub pulse: u32,
}

/// Where the previous tick's steps left the output, in timer ticks relative
/// to the start of the tick being planned (so usually negative): the next
/// step must keep the minimum spacing from the last one, and after a
/// reversal DIR (which changes when the last pulse has ended) needs its
/// setup time before the next rising edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Prev {
    pub dir: Dir,
    /// the last rising edge (`FAR` when there was none lately)
    pub rise: i32,
    /// when DIR may change: the end of the last pulse, or a tick boundary
    pub end: i32,
    /// when DIR last changed (`FAR` when not lately): a step in `dir`
    /// waits for its setup time from then
    pub dir_since: i32,
}

/// "Long ago": far enough that no spacing rule reaches into this tick.
pub const FAR: i32 = -(1 << 30);

impl Prev {
    /// No step lately, DIR as given: a reversal waits its setup time from
    /// the start of the tick.
    pub const fn idle(dir: Dir) -> Prev {
        Prev { dir, rise: FAR, end: 0, dir_since: FAR }
    }

    /// The earliest time in this tick a step in `dir` may rise.
    #[inline]
    pub fn earliest(&self, dir: Dir, t: &StepTiming) -> u32 {
        let spaced = self.rise.saturating_add(t.min_period as i32);
        let changed = if dir == self.dir { self.dir_since } else { self.end };
        spaced.max(changed.saturating_add(t.dir_setup as i32)).max(0) as u32
    }

    /// The same edges seen from the next tick, after `plan` was emitted.
    /// DIR takes the plan's direction at the tick's first segment, at
    /// `end` (an empty plan may turn it ahead of a reversal whose setup
    /// time does not fit in this tick).
    #[inline]
    pub fn after(&self, plan: &StepPlan, t: &StepTiming) -> Prev {
        let len = t.tick_len as i32;
        let back = |v: i32| v.saturating_sub(len).max(FAR);
        let dir_since = if plan.dir != self.dir { self.end - len } else { back(self.dir_since) };
        if plan.count == 0 {
            // a tick without steps is filled to its end: DIR may change from
            // the next tick's start
            return Prev { dir: plan.dir, rise: back(self.rise), end: 0, dir_since };
        }
        let rise = plan.at(plan.count as u32 - 1) as i32 - len;
        let end = rise + t.pulse as i32;
        // silence of at least a pulse after the last pulse fills the tick
        // too: the step output ends the tick's segments at its end then,
        // with this plan's DIR (`Prev::fills`), so DIR may change from the
        // next tick's start, not from the pulse's end
        let end = if Prev::fills(end, t) { 0 } else { end };
        Prev { dir: plan.dir, rise, end, dir_since }
    }

    /// Whether a pulse ending at `end` (relative to the next tick's start)
    /// leaves the rest of its tick to a silence of its own: at least a
    /// pulse long, so at least as long as the shortest segment the step
    /// output can reload (the pulse's floor).
    #[inline]
    pub fn fills(end: i32, t: &StepTiming) -> bool {
        -end >= t.pulse as i32
    }
}

/// Plans the next tick. `from`/`to` are the commanded positions (Q16 steps)
/// at the start and end of the tick; `emitted` the steps emitted (or
/// committed) so far; `prev` where the last steps left the output.
/// Uses 32-bit divisions only (UDIV on Cortex-M4). Inlined: out of line,
/// its call and its 64-bit arguments on the stack cost the tick 6
/// instructions more (counted on an emulated Cortex-M4).
#[inline(always)]
pub fn plan(from: i64, to: i64, emitted: i64, prev: &Prev, t: &StepTiming) -> StepPlan {
    let whole = crate::q16::round(to);
    let wanted = whole - emitted;
    if wanted == 0 {
        return StepPlan { dir: prev.dir, ..StepPlan::default() };
    }
    let dir = if wanted > 0 { Dir::Forward } else { Dir::Reverse };
    // no step fits this tick: DIR turns now all the same, so that a setup
    // time longer than a tick still runs out
    let none = StepPlan { dir, ..StepPlan::default() };
    let earliest = prev.earliest(dir, t);
    // (max(1) lets the compiler drop the division-by-zero panic)
    let min_period = t.min_period.max(1);
    // Every rising edge falls inside this tick (the pulse counter has it
    // when the next tick reads it); what does not fit waits.
    let room = t.tick_len.saturating_sub(1);
    if earliest > room {
        return none;
    }
    let max_fit = 1 + (room - earliest) / min_period;
    let count = (wanted.unsigned_abs()).min(max_fit as u64) as u32;
    let travel = (to - from).unsigned_abs();
    let on_schedule = emitted == crate::q16::round(from);
    let (first, first_frac, period, frac) = if on_schedule && travel > 0 && travel < 1 << 31 {
        // The first half-step boundary after `from` in the direction of motion.
        let boundary = if dir == Dir::Forward {
            (crate::q16::from_steps(emitted) + crate::q16::HALF) - from
        } else {
            from - (crate::q16::from_steps(emitted) - crate::q16::HALF)
        };
        // The first step rounded to the nearest timer tick, the period to
        // 1/256 tick (so every step of the tick is within half a tick of
        // its exact instant). tick_len < 2^15, boundary ≤ 2^16 and, for the
        // fraction, travel < 2^24 keep all in 32 bits: UDIVs, no
        // __aeabi_uldivmod.
        let (len, travel) = (t.tick_len.min(0x7FFF), (travel as u32).max(1));
        let (first, first_frac) = q8_ratio((boundary.clamp(0, 1 << 16) as u32) * len, travel);
        let (mut period, mut frac) = q8_ratio(len << 16, travel);
        if period < min_period {
            (period, frac) = (min_period, 0);
        }
        (first, first_frac, period, frac)
    } else {
        // Late (catching up on steps not emitted in time): the first as soon
        // as allowed, the rest spread evenly over the tick.
        let period = (t.tick_len / count.saturating_add(1).max(1)).max(min_period);
        (0, 0, period, 0)
    };
    // (compared rounded: a first step already as late as allowed keeps its
    // fraction, and with it the exact spacing of the steps after it)
    let rounded = first + ((first_frac as u32 + 128) >> 8);
    let (first, first_frac) = if rounded < earliest { (earliest, 0) } else { (first, first_frac) };
    if first > room {
        return none;
    }
    let count = count.min(1 + (room - first) / period);
    let p = StepPlan { count: count as u16, dir, first, period, first_frac, frac };
    // The fractions can carry the last step past the tick: drop it, unless
    // only the rounding did (its exact instant is inside the tick, within
    // half a timer tick of its end: it rises with the next tick's start,
    // still long before the next tick reads the pulse counter).
    if p.at(count - 1) > t.tick_len {
        return StepPlan { count: count as u16 - 1, ..p };
    }
    p
}

pub mod book;
pub mod pipe;

pub use book::StepBook;

/// `num / den` as a whole part and a fraction in 1/256, rounded: 32-bit
/// UDIVs only (the fraction needs `den` < 2^24, else it is 0).
#[inline]
fn q8_ratio(num: u32, den: u32) -> (u32, u8) {
    let (whole, rest) = (num / den, num % den);
    let frac = if den < 1 << 24 { ((rest << 8) + den / 2) / den } else { 0 };
    if frac > 255 {
        (whole + 1, 0)
    } else {
        (whole, frac as u8)
    }
}

#[cfg(test)]
mod pinned_tests;
#[cfg(test)]
mod tests;
