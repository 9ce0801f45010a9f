//! Step scheduling for a stepper (or a servo taking step/dir): per tick, how
//! many steps to emit in the next tick, when the first one falls and the
//! period between them, so steps are evenly spaced *across* tick boundaries
//! (each step sits where the commanded position crosses a half step, as in
//! Klipper's stepcompress and Didge's evenly spaced steps).
//!
//! The core closes on the steps really emitted (read back from hardware), so
//! a step that was planned but not emitted is planned again, never lost.

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
    /// timer ticks from the start of the tick to the first step
    pub first: u32,
    /// timer ticks between steps
    pub period: u32,
}

/// The hardware seam: emit a plan; count what was really emitted.
pub trait StepOutput {
    fn emit(&mut self, plan: &StepPlan);
    /// A free-running, wrapping 16-bit count of the pulses emitted.
    fn emitted(&mut self) -> u16;
    /// Stop at once (E-stop, alarm): abort any pulses not yet emitted.
    fn halt(&mut self);
}

/// Timing constants of the step generator, in its timer's ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepTiming {
    /// timer ticks per control tick
    pub tick_len: u32,
    /// shortest allowed period (pulse high + low)
    pub min_period: u32,
    /// DIR to first STEP setup time
    pub dir_setup: u32,
    /// STEP pulse high time (the drivers program it; half of min_period at most)
    pub pulse: u32,
}

/// Plans the next tick. `from`/`to` are the commanded positions (Q16 steps)
/// at the start and end of the tick; `emitted` the steps emitted so far.
/// Uses one 32-bit division (a single UDIV on Cortex-M4) per tick with steps.
#[inline]
pub fn plan(from: i64, to: i64, emitted: i64, last_dir: Dir, t: &StepTiming) -> StepPlan {
    let whole = (to + (1 << 15)) >> 16;
    let wanted = whole - emitted;
    if wanted == 0 {
        return StepPlan { count: 0, dir: last_dir, first: 0, period: 0 };
    }
    let dir = if wanted > 0 { Dir::Forward } else { Dir::Reverse };
    let setup = if dir != last_dir { t.dir_setup } else { 0 };
    let min_period = t.min_period.max(1); // lets the compiler drop the div-by-zero panic
    let max_fit = 1 + (t.tick_len.saturating_sub(setup + 1)) / min_period;
    let count = (wanted.unsigned_abs()).min(max_fit as u64) as u32;
    let travel = (to - from).unsigned_abs();
    let on_schedule = emitted == (from + (1 << 15)) >> 16;
    let (first, period) = if on_schedule && travel > 0 && travel < 1 << 31 {
        // The first half-step boundary after `from` in the direction of motion.
        let boundary = if dir == Dir::Forward {
            ((emitted << 16) + (1 << 15)) - from
        } else {
            from - ((emitted << 16) - (1 << 15))
        };
        // tick_len < 2^16 and travel < 2^31: a 32-bit UDIV, not __aeabi_uldivmod.
        let period = (t.tick_len.min(0xFFFF) << 16) / (travel as u32).max(1);
        let first = ((boundary.max(0) as u64 * period as u64) >> 16) as u32;
        (first, period.max(min_period))
    } else {
        // Late (catching up on steps not emitted in time): the first at once,
        // the rest spread evenly over the tick.
        let period = (t.tick_len / count.saturating_add(1).max(1)).max(min_period);
        (0, period)
    };
    // Every step's edge must fall inside this tick, so the pulse counter has
    // it when the next tick reads it: a step planned past the tick's end
    // would be counted late and planned twice. What does not fit waits.
    // (The firmware lets a pulse still high at the tick's end finish.)
    let first = first.max(setup);
    let room = t.tick_len.saturating_sub(1);
    if first > room {
        return StepPlan { count: 0, dir: last_dir, first: 0, period: 0 };
    }
    let count = count.min(1 + (room - first) / period);
    StepPlan { count: count as u16, dir, first, period }
}

#[cfg(test)]
mod tests;
