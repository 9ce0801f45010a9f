//! The self-test's profile for the generator, and its books for the judge
//! (`polyturn_sync::selftest`): the glue the app runs, host-tested here.

pub mod playback;

use super::{Generator, Period, Periods, Profile, Segment, TIMER_HZ};
use polyturn_sync::selftest::{Books, Kind, Plan, LEGS};

/// The generator the app keeps: it owns its segments.
pub type BenchGenerator = Generator<Periods<[Segment; LEGS]>>;

/// The judge's legs as the generator's segments, one for one: a rest is a
/// hold at 0 rpm (idle periods).
pub fn segments(plan: &Plan) -> [Segment; LEGS] {
    plan.legs.map(|l| match l.kind {
        Kind::Rest | Kind::Hold => Segment::Hold { rpm: l.from_rpm, ms: l.ms },
        Kind::Ramp => Segment::Ramp { from: l.from_rpm, to: l.to_rpm, ms: l.ms },
    })
}

/// The generator for `plan`, and the program that starts TIM9; `None` if
/// the generator cannot play it (the judge then fails the test: no books).
pub fn start(plan: &Plan) -> Option<(BenchGenerator, [super::program::Op; 15])> {
    let segs = segments(plan);
    let profile = Profile::new(plan.cpr, &segs).ok()?;
    Generator::start(&profile, Periods::owning(plan.cpr, segs))
}

/// What the generator has made so far, for the judge. `ms` is where the
/// booked periods end, in TIM9's own clock.
pub fn books<I: Iterator<Item = Period>>(g: &Generator<I>) -> Books {
    let e = g.ledger();
    Books {
        counts: e.position(),
        indexes: e.indexes(),
        ms: (e.clocks() / (TIMER_HZ as u64 / 1000)).min(u32::MAX as u64) as u32,
        running: g.running(),
        last_index: e.last_index(),
        latency_cycles: g.worst_latency(),
    }
}

#[cfg(test)]
mod tests;
