//! An incremental encoder as the board sees it: the A/B cycle of RM0383
//! Table 53 (counting up: (A,B) = (0,0) → (1,0) → (1,1) → (0,1)), the
//! count's value in state (0,0) a multiple of 4, and A's rising edges
//! latched as the board latches them (`polyturn_sync::edges`): the count
//! after the edge and the whole µs it fell in.
//!
//! Ideal, count c holds the angles whose position u = angle·E/2π is within
//! ½ of c, and an index is at angle 0 of every turn. A real disc is not
//! ideal; each imperfection is a field, 0 by default:
//! - eccentricity: every edge moved by `eccentricity_counts`·sin(angle),
//!   once a turn (a disc off its shaft's centre by e at code radius r moves
//!   its edges by e/r radians: 0.1 % is 0.38 count on a 600-line disc);
//! - quadrature error: B's edges moved by `quadrature_counts` (A and B not
//!   at 90°: ±3 % of a cycle is ±0.12 count);
//! - duty error: A's falling edge moved by `duty_counts`.
//!
//! Glitches (dropped or extra counts) are injected for fault tests.

use crate::round::floor;
use polyturn_sync::edges::EdgeRegs;
use std::f64::consts::TAU;

/// The disc's imperfections, in counts (see the module's header).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Disc {
    pub eccentricity_counts: f64,
    pub quadrature_counts: f64,
    pub duty_counts: f64,
}

#[derive(Clone, Debug, Default)]
pub struct Encoder {
    pub counts_per_rev: u32,
    pub disc: Disc,
    /// (tick, extra counts): injected at that tick
    pub glitches: Vec<(u64, i64)>,
    offset: i64,
    last_turn: Option<i64>,
    /// angles well inside the last turn (its turn without a division: the
    /// edges, where rounding could tell otherwise, are left to `floor`)
    inside_turn: (f64, f64),
    /// A's last rise as the registers hold it (the count latched, and its
    /// stamp): worked out once a rise, not every tick the tick reads them
    rise: Option<EdgeRegs>,
    /// the last two positions worked out, (angle, eccentricity, u): a tick
    /// asks for each angle two or three times
    seen: [(f64, f64, f64); 2],
}

/// Stamps a second: the board's TIM5 at 1 MHz.
pub const STAMP_HZ: f64 = 1e6;
/// The stamp at t = 0: not 0, so runs cross the stamp's wrap.
pub const STAMP_ORIGIN: f64 = 60_000.0;

impl Encoder {
    pub fn new(counts_per_rev: u32) -> Encoder {
        Encoder { counts_per_rev, ..Encoder::default() }
    }

    pub fn with_disc(counts_per_rev: u32, disc: Disc) -> Encoder {
        Encoder { disc, ..Encoder::new(counts_per_rev) }
    }

    /// The edge position u of the lathe's angle, counts.
    pub fn position(&self, angle: f64) -> f64 {
        let e = self.counts_per_rev as f64;
        let ideal = angle / TAU * e;
        // (no sine for a true disc: the simulator's hottest call)
        match self.disc.eccentricity_counts {
            0.0 => ideal,
            ecc => ideal + ecc * angle.sin(),
        }
    }

    /// `position`, from `seen` when it holds `angle` on this disc.
    fn u_of(&mut self, angle: f64) -> f64 {
        let ecc = self.disc.eccentricity_counts;
        if let Some(&(_, _, u)) = self.seen.iter().find(|s| s.0 == angle && s.1 == ecc) {
            return u;
        }
        let u = self.position(angle);
        self.seen = [self.seen[1], (angle, ecc, u)];
        u
    }

    /// The count at `angle` (glitches due by `tick` applied).
    pub fn count(&mut self, angle: f64, tick: u64) -> i64 {
        for &(t, extra) in &self.glitches {
            if t == tick {
                self.offset += extra;
            }
        }
        let u = self.u_of(angle);
        self.count_at(u) + self.offset
    }

    /// Where count `n` begins, counting up (position u, counts): the edge
    /// of `count_at`'s cycle that takes it there.
    pub fn boundary_up(&self, n: i64) -> f64 {
        let j = (n - 1).div_euclid(4);
        let Disc { quadrature_counts: q, duty_counts: d, .. } = self.disc;
        let edges = [0.0, 1.0 + q, 2.0 + d, 3.0 + q];
        4.0 * j as f64 + 0.5 + edges[(n - 1 - 4 * j) as usize]
    }

    /// The count at position u: the edges of u's cycle at or below it.
    fn count_at(&self, u: f64) -> i64 {
        let v = u - 0.5;
        let j = floor(v * 0.25); // (÷4 exactly, without a division's latency)
        let w = v - 4.0 * j;
        let Disc { quadrature_counts: q, duty_counts: d, .. } = self.disc;
        let edges = [0.0, 1.0 + q, 2.0 + d, 3.0 + q];
        4 * j as i64 + edges.iter().filter(|&&b| b <= w).count() as i64
    }

    /// Follows the lathe from `angle_before` (at `t − dt`) to `angle` (at
    /// `t`), turning at a steady speed between, and latches A's last rise.
    pub fn follow(&mut self, angle_before: f64, angle: f64, t: f64, dt: f64) {
        let (u0, u1) = (self.u_of(angle_before), self.u_of(angle));
        if u0 == u1 {
            return;
        }
        // A rises at the cycle's first edge counting up, and at its third
        // (A's fall, moved by the duty error) counting down
        let up = u1 > u0;
        let phase = if up { 0.5 } else { 2.5 + self.disc.duty_counts };
        let (lo, hi) = (u0.min(u1), u0.max(u1));
        let mut b = floor((lo - phase) * 0.25) * 4.0 + phase;
        let mut crossed = (f64::INFINITY, f64::NEG_INFINITY);
        while b <= hi {
            if b > lo {
                crossed = (crossed.0.min(b), crossed.1.max(b));
            }
            b += 4.0;
        }
        // the last rise in time: the highest going up, the lowest going down
        let b = Some(if up { crossed.1 } else { crossed.0 }).filter(|b| b.is_finite());
        if let Some(b) = b {
            let at = t - dt + dt * (b - u0) / (u1 - u0);
            let after = if up { b + 0.5 } else { b - 0.5 };
            let count = after.round() as i64 + self.offset;
            let stamp = floor(STAMP_ORIGIN + at * STAMP_HZ) as i64;
            self.rise = Some(EdgeRegs { count: count as u16, stamp: stamp as u16 });
        }
    }

    /// The registers the tick reads: the count and the stamp of A's last rise.
    pub fn edge_regs(&self) -> Option<EdgeRegs> {
        self.rise
    }

    /// The raw 16-bit counter value latched at an index crossed since the
    /// last call, if any.
    pub fn index(&mut self, angle: f64) -> Option<u16> {
        let (lo, hi) = self.inside_turn;
        let turn = match self.last_turn {
            Some(t) if lo < angle && angle < hi => t,
            _ => {
                let t = floor(angle / TAU) as i64;
                self.inside_turn = (t as f64 * TAU + 1e-6, (t + 1) as f64 * TAU - 1e-6);
                t
            }
        };
        let last = self.last_turn.replace(turn)?;
        if turn == last {
            return None;
        }
        let at = turn.max(last);
        Some((at * self.counts_per_rev as i64 + self.offset) as u16)
    }
}

#[cfg(test)]
#[path = "encoder_tests.rs"]
mod tests;
