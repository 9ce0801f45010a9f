//! An incremental encoder: counts = round(angle·E/2π) (the angle of count c
//! is the middle of its interval), an index at angle 0 of every turn, and
//! optional glitches (dropped or extra counts) for fault tests.

use std::f64::consts::TAU;

#[derive(Clone, Debug, Default)]
pub struct Encoder {
    pub counts_per_rev: u32,
    /// (tick, extra counts): injected at that tick
    pub glitches: Vec<(u64, i64)>,
    offset: i64,
    last_turn: Option<i64>,
}

impl Encoder {
    pub fn new(counts_per_rev: u32) -> Encoder {
        Encoder { counts_per_rev, ..Encoder::default() }
    }

    pub fn count(&mut self, angle: f64, tick: u64) -> i64 {
        for &(t, extra) in &self.glitches {
            if t == tick {
                self.offset += extra;
            }
        }
        (angle / TAU * self.counts_per_rev as f64).round() as i64 + self.offset
    }

    /// The raw 16-bit counter value latched at an index crossed since the
    /// last call, if any.
    pub fn index(&mut self, angle: f64) -> Option<u16> {
        let turn = (angle / TAU).floor() as i64;
        let last = self.last_turn.replace(turn)?;
        if turn == last {
            return None;
        }
        let at = turn.max(last);
        Some((at * self.counts_per_rev as i64 + self.offset) as u16)
    }
}
