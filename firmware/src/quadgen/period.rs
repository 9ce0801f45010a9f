//! One TIM9 update period: its prescaler and half-length in counter ticks, and
//! which way its two edges count. The register values come from here
//! (`ccr`), and so do the edges' instants (`edge_offsets`) that the tests
//! compare with the model's pins.

use super::{HALF_MIN_CLOCKS, LEAD, PSC_MAX};

/// Which way a period's two edges count on the lathe-encoder input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// A toggles first, then B: TIM3 counts up twice (Table 53).
    Forward,
    /// B first, then A: two counts down.
    Reverse,
    /// No edge: compare values beyond ARR.
    Idle,
}

/// One update period: (PSC + 1) × 2 × `half` CK_INT cycles; a moving one
/// toggles one output `LEAD` ticks after its update event and the other
/// `half` ticks later, so its edges are `half` ticks apart and as far from
/// the next period's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Period {
    pub psc: u16,
    pub half: u16,
    pub motion: Motion,
}

/// An idle period: 0.5 ms without edges.
pub const IDLE: Period = Period { psc: 0, half: 24_000, motion: Motion::Idle };

/// Compare value that no count reaches: an idle period's ARR is below it.
const NEVER: u16 = 0xFFFF;

/// Longest moving period, CK_INT cycles: PSC_MAX with a full 16-bit count.
pub const MAX_CLOCKS: u64 = (PSC_MAX as u64 + 1) << 16;

impl Period {
    /// A moving period as close to `clocks` CK_INT cycles as an even count
    /// of ticks allows, with the smallest prescaler that fits; none faster
    /// than the index allows (`HALF_MIN_CLOCKS`); idle if longer than
    /// `MAX_CLOCKS`.
    pub fn moving(clocks: u64, motion: Motion) -> Period {
        if clocks > MAX_CLOCKS || motion == Motion::Idle {
            return IDLE;
        }
        let div = clocks.div_ceil(1 << 16).max(1);
        let half = (clocks / div).div_ceil(2).clamp(HALF_MIN_CLOCKS.div_ceil(div as u32) as u64, 1 << 15);
        Period { psc: (div - 1) as u16, half: half as u16, motion }
    }

    pub const fn arr(&self) -> u16 {
        (2 * self.half as u32 - 1) as u16
    }

    pub const fn clocks(&self) -> u32 {
        (self.psc as u32 + 1) * 2 * self.half as u32
    }

    /// (CCR1, CCR2): the first edge of the period `LEAD` ticks after its
    /// update event, the second `half` later; A first forward, B first in
    /// reverse; none when idle.
    pub const fn ccr(&self) -> [u16; 2] {
        let (first, second) = (LEAD, LEAD + self.half);
        match self.motion {
            Motion::Forward => [first, second],
            Motion::Reverse => [second, first],
            Motion::Idle => [NEVER, NEVER],
        }
    }

    /// Signed counts the period makes: ±2, or 0 when idle.
    pub const fn counts(&self) -> i64 {
        match self.motion {
            Motion::Forward => 2,
            Motion::Reverse => -2,
            Motion::Idle => 0,
        }
    }

    /// CK_INT cycles from the period's update event to its two edges.
    pub const fn edge_offsets(&self) -> [u32; 2] {
        let tick = self.psc as u32 + 1;
        [tick * LEAD as u32, tick * (LEAD + self.half) as u32]
    }
}
