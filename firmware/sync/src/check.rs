//! The encoder check: what the lathe encoder really counts,
//! measured while the machinist turns the chuck by hand (or runs the lathe
//! slowly). Encoders are often not what the label says (a "1024" that is
//! 1000, ×4 decoding forgotten, counts lost to noise), and a wrong `cpr`
//! cuts the wrong number of flats.
//!
//! Fed at low priority (`Controller::service`, about every millisecond)
//! with copies the tick keeps: the lathe's count, and the count latched in
//! hardware at the last index edge (TIM3_CH3 capture) with the number of
//! index edges so far. Time is the tick count, so the figures do not
//! depend on how regularly the service runs.

/// What the controller hands the check at each sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// control ticks since boot
    pub ticks: u64,
    /// lathe position, counts
    pub counts: i64,
    /// index edges seen since boot (wraps)
    pub indexes: u32,
    /// the count latched at the last index edge
    pub last_index: i64,
}

/// The check's running figures.
#[derive(Clone, Copy, Debug)]
pub struct EncoderCheck {
    last: Sample,
    /// samples before this tick are the "hands off" window: any count
    /// there is chatter (an encoder sitting on an edge, or noise)
    still_until: u64,
    /// the most counts a tick can plausibly bring (`Derived`)
    max_counts_per_tick: i64,
    forward: u64,
    backward: u64,
    jumps: u32,
    chatter: u64,
    indexes: u32,
    skipped: u32,
    /// the last index's count, and `backward` then (a gap with motion in
    /// both directions is no revolution)
    prev_index: Option<(i64, u64, u64)>,
    gaps: u32,
    gap_min: i64,
    gap_max: i64,
    gap_sum: i64,
}

/// The figures, for the console's `check-encoder` reply.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EncoderReport {
    /// net counts since the still window (positive: counting up)
    pub moved: i64,
    /// counts against the main direction of travel
    pub backward: u64,
    /// samples that moved further than the lathe can turn
    pub jumps: u32,
    /// counts during the still window
    pub chatter: u64,
    /// the still window is over
    pub still_done: bool,
    pub indexes: u32,
    /// index gaps not measured (two indexes in one sample, or a reversal)
    pub skipped: u32,
    /// counts between consecutive index edges: (gaps, min, max)
    pub gap: Option<(u32, i64, i64)>,
    /// the cpr to set, when at least two gaps agree within one count
    pub cpr: Option<u32>,
}

impl EncoderCheck {
    /// Starts at `at`; the first `still_ticks` are the hands-off window.
    pub fn new(at: Sample, still_ticks: u64, max_counts_per_tick: i64) -> EncoderCheck {
        EncoderCheck {
            last: at,
            still_until: at.ticks + still_ticks,
            max_counts_per_tick: max_counts_per_tick.max(1),
            forward: 0,
            backward: 0,
            jumps: 0,
            chatter: 0,
            indexes: 0,
            skipped: 0,
            prev_index: None,
            gaps: 0,
            gap_min: i64::MAX,
            gap_max: 0,
            gap_sum: 0,
        }
    }

    pub fn sample(&mut self, s: Sample) {
        let d = s.counts - self.last.counts;
        let ticks = s.ticks.saturating_sub(self.last.ticks).max(1) as i64;
        if d.abs() > self.max_counts_per_tick.saturating_mul(ticks) {
            self.jumps = self.jumps.saturating_add(1);
        }
        if s.ticks <= self.still_until {
            self.chatter += d.unsigned_abs();
        } else if d > 0 {
            self.forward += d as u64;
        } else {
            self.backward += d.unsigned_abs();
        }
        match s.indexes.wrapping_sub(self.last.indexes) {
            0 => {}
            1 => self.on_index(s.last_index),
            n => {
                // more than one index since the last sample: their counts
                // are gone, only the last one is known
                self.indexes = self.indexes.saturating_add(n);
                self.skipped = self.skipped.saturating_add(n);
                self.prev_index = Some((s.last_index, self.forward, self.backward));
            }
        }
        self.last = s;
    }

    fn on_index(&mut self, at: i64) {
        self.indexes = self.indexes.saturating_add(1);
        if let Some((prev, fwd, back)) = self.prev_index {
            let both_ways = self.forward != fwd && self.backward != back;
            if both_ways {
                self.skipped = self.skipped.saturating_add(1);
            } else {
                let gap = (at - prev).abs();
                self.gaps += 1;
                self.gap_min = self.gap_min.min(gap);
                self.gap_max = self.gap_max.max(gap);
                self.gap_sum = self.gap_sum.saturating_add(gap);
            }
        }
        self.prev_index = Some((at, self.forward, self.backward));
    }

    pub fn report(&self) -> EncoderReport {
        let moved = self.forward as i64 - self.backward as i64;
        let against = if moved >= 0 { self.backward } else { self.forward };
        let gap = (self.gaps > 0).then_some((self.gaps, self.gap_min, self.gap_max));
        // Two gaps or more that agree within a count: the encoder's real
        // counts per revolution (the capture latches the count in
        // hardware, so a good encoder gives a spread of zero).
        let cpr = gap.filter(|&(n, lo, hi)| n >= 2 && hi - lo <= 1 && lo > 0).map(|(n, ..)| {
            let n = n as i64;
            ((self.gap_sum + n / 2) / n).min(u32::MAX as i64) as u32
        });
        EncoderReport {
            moved,
            backward: against,
            jumps: self.jumps,
            chatter: self.chatter,
            still_done: self.last.ticks > self.still_until,
            indexes: self.indexes,
            skipped: self.skipped,
            gap,
            cpr,
        }
    }
}

#[cfg(test)]
mod report_tests;
#[cfg(test)]
mod tests;
