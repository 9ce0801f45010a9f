//! A speed profile of the simulated lathe, and the update periods that
//! play it. Integer maths only: rpm are whole numbers, ramps are
//! interpolated in milli-rpm at each period's start.

use super::period::{Motion, Period, IDLE};
use super::{MAX_COUNT_RATE, TIMER_HZ};

/// One piece of the profile. Rpm are signed: negative turns backward, so a
/// `Hold` at -n right after one at +n reverses at an update event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Segment {
    /// From `from` rpm to `to` rpm, linearly over `ms` milliseconds.
    Ramp { from: i32, to: i32, ms: u32 },
    /// `rpm` for `ms` milliseconds.
    Hold { rpm: i32, ms: u32 },
}

impl Segment {
    const fn ends(&self) -> (i32, i32, u32) {
        match *self {
            Segment::Ramp { from, to, ms } => (from, to, ms),
            Segment::Hold { rpm, ms } => (rpm, rpm, ms),
        }
    }

    fn clocks(&self) -> u64 {
        self.ends().2 as u64 * (TIMER_HZ as u64 / 1000)
    }

    /// Milli-rpm `t` CK_INT cycles into the segment.
    fn mrpm_at(&self, t: u64) -> i64 {
        let (from, to, _) = self.ends();
        let span = self.clocks().max(1) as i128;
        let (a, b) = (from as i128 * 1000, to as i128 * 1000);
        (a + (b - a) * t.min(span as u64) as i128 / span) as i64
    }
}

/// Why a profile cannot be played.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// The index spans one update period (two counts): cpr must be even,
    /// and at least 4 for the index to fall between pulses.
    Cpr(u32),
    /// Segment `segment` exceeds `max_rpm` (`max_rpm`'s bound).
    TooFast { segment: usize, max_rpm: u32 },
}

/// Highest |rpm| the index's timing bound allows at `cpr` counts per
/// revolution: `MAX_COUNT_RATE` × 60 / cpr.
pub const fn max_rpm(cpr: u32) -> u32 {
    (MAX_COUNT_RATE as u64 * 60 / cpr as u64) as u32
}

/// A checked profile.
#[derive(Clone, Copy, Debug)]
pub struct Profile<'a> {
    cpr: u32,
    segments: &'a [Segment],
}

impl<'a> Profile<'a> {
    pub fn new(cpr: u32, segments: &'a [Segment]) -> Result<Profile<'a>, Error> {
        if cpr < 4 || !cpr.is_multiple_of(2) {
            return Err(Error::Cpr(cpr));
        }
        let max = max_rpm(cpr);
        for (i, s) in segments.iter().enumerate() {
            let (a, b, _) = s.ends();
            if a.unsigned_abs().max(b.unsigned_abs()) > max {
                return Err(Error::TooFast { segment: i, max_rpm: max });
            }
        }
        Ok(Profile { cpr, segments })
    }

    pub fn cpr(&self) -> u32 {
        self.cpr
    }

    /// The update periods that play the profile, in order.
    pub fn periods(&self) -> Periods<&'a [Segment]> {
        Periods::owning(self.cpr, self.segments)
    }
}

/// Iterator over a profile's periods. A period is timed from the speed at
/// its start; one that runs past its segment's end makes the next segment
/// start that much into it, so the timeline never drifts. `S` is a slice
/// or an array: the firmware's generator owns its segments.
#[derive(Clone, Debug)]
pub struct Periods<S> {
    cpr: u32,
    segments: S,
    seg: usize,
    /// CK_INT cycles since the current segment began
    t: u64,
}

impl<S: AsRef<[Segment]>> Periods<S> {
    /// The periods of `segments`, checked by `Profile::new` first.
    pub fn owning(cpr: u32, segments: S) -> Periods<S> {
        Periods { cpr, segments, seg: 0, t: 0 }
    }
}

impl<S: AsRef<[Segment]>> Iterator for Periods<S> {
    type Item = Period;

    fn next(&mut self) -> Option<Period> {
        let segments = self.segments.as_ref();
        while self.t >= segments.get(self.seg)?.clocks() {
            self.t -= segments[self.seg].clocks();
            self.seg += 1;
        }
        let p = period_at(segments[self.seg].mrpm_at(self.t), self.cpr);
        self.t += p.clocks() as u64;
        Some(p)
    }
}

/// The period of two counts at `mrpm` milli-rpm: 2 × TIMER_HZ × 60 000 /
/// (|mrpm| × cpr) cycles; idle at 0 or too slow for `Period::moving`.
fn period_at(mrpm: i64, cpr: u32) -> Period {
    if mrpm == 0 {
        return IDLE;
    }
    let clocks = 2 * TIMER_HZ as u64 * 60_000 / (mrpm.unsigned_abs() * cpr as u64);
    Period::moving(clocks, if mrpm > 0 { Motion::Forward } else { Motion::Reverse })
}
