//! The bench self-test's signal generator: a lathe encoder made by TIM9, to
//! be jumpered to the lathe-encoder inputs (A: PA2 → PA6, B: PA3 → PA7,
//! index: PA4 → PB0), so the real gearbox runs against a known lathe.
//!
//! **A and B** are TIM9's channels 1 and 2 (PA2/PA3, AF3) in output compare
//! toggle mode (RM0383 §14.4.6 OCxM = 011), with CCR, ARR and PSC buffered
//! (§14.4.6 OCxPE, §14.4.1 ARPE, §14.3.1). Each update period toggles each
//! output once, `LEAD` ticks and `LEAD + half` ticks after its update event
//! (`Period`): two quadrature counts, evenly spaced, hardware-timed. Which
//! output goes first is the direction; new values take effect at an update
//! event, so a speed change or a reversal happens exactly on a period
//! boundary and no count is lost or doubled (`Ledger`).
//!
//! **The index** is PA4, a push-pull GPIO written by the update interrupt
//! (TIM1_BRK_TIM9, UIE) as the first thing it does, high for the period
//! that crosses [n·cpr, n·cpr + 2] (`Ledger::index_in`). Its edge is
//! software-timed and must fall between the period's two edges, so TIM3
//! latches n·cpr + 1 whichever way the lathe turns:
//!
//! * after the first edge, at (PSC + 1) × `LEAD` cycles: the interrupt
//!   needs at least `ENTRY_MIN` cycles to enter (Cortex-M4, 12 cycles with
//!   no wait state), so PSC + 1 + `MARGIN` ≤ `ENTRY_MIN`, i.e. PSC ≤
//!   `PSC_MAX`;
//! * before the second, at (PSC + 1)(`LEAD` + half) cycles: with the
//!   interrupt's worst latency `LATENCY_MAX` (update event to the index
//!   write), (PSC + 1) × half ≥ `LATENCY_MAX` + `MARGIN` =
//!   `HALF_MIN_CLOCKS`. Half a period is one count, so the count rate is at
//!   most TIMER_HZ / `HALF_MIN_CLOCKS` = `MAX_COUNT_RATE` (12 786 counts/s:
//!   319 rpm at 2400 counts per revolution; `profile::max_rpm`).
//!
//! `ENTRY_MIN` is the exception entry (12 cycles; 6 when tail-chained)
//! plus the handler's code before its write (the critical section and the
//! generator's borrow, tens of instructions): 12 is a floor. An index
//! written too early or too late latches another count than n·cpr + 1,
//! which the self-test's judge rejects (`Failure::IndexLate`); the handler
//! also reads TIM9_CNT after the write and the books keep the worst
//! (`Generator::worst_latency`, the reply's `index_latency_cycles`).
//!
//! `LATENCY_MAX` = 7 500 cycles is the emulator's bound on the real image
//! (`bash .ci/emu`, its `selftest … index latency` lines, which fail above
//! it) with about 20 % to spare: 6 028 cycles at 300 rpm and 6 085 at the
//! top speed, the tick and its plan running. The interrupt sits below the tick (level 1; the E-stop, above
//! it, is 0, and the tick's step plan below it, 2): at level 3 it waits
//! for the E-stop's handler, the tick and its plan, the longest section
//! under the tick's lock, embassy's TIM5 handler at the same level, every
//! global critical section (BASEPRI, `app/cs.rs`: embassy's time driver
//! holds one for its whole TIM5 handler and for each timer it schedules),
//! and its own entry (12) and prologue. A measurement, not a proof: the
//! bench procedure asks for the reply's figure at the top speed. `MARGIN`
//! (8 cycles) covers TIM3's input path: A, B and the index go through the
//! same 8-sample filter (`app::drivers`). defmt's log lines (80 µs) are
//! kept out while the generator plays. Moving TIM9 alone above the tick's
//! plan, or the index to a timer's compare output, would shorten it.
//!
//! The slowest moving period is `period::MAX_CLOCKS` (PSC_MAX with a full
//! count): 732 counts/s; slower parts of a profile are idle periods.
//!
//! Wiring in the app (`app/selftest.rs`): RCC_APB2ENR.TIM9EN; PA4 output
//! push-pull, low; TIM1_BRK_TIM9 enabled at level 3 (`board::PRIORITIES`);
//! the generator put where the handler finds it and `Generator::start`'s
//! program applied inside the critical section, which masks the interrupt
//! (its last write starts the counter one tick before update event 0,
//! which interrupts as soon as the section ends); then PA2/PA3 from inputs
//! with pull-downs to AF3 (the timer drives them low already). The handler
//! applies `Generator::index_op` first, then `on_update`'s program (whose
//! first write repeats the index level): finding the next period divides,
//! and the index must not wait for it.

pub mod bench;
pub mod ledger;
pub mod period;
pub mod profile;
pub mod program;

pub use ledger::Ledger;
pub use period::{Motion, Period};
pub use profile::{max_rpm, Error, Periods, Profile, Segment};

use program::Op;

/// TIM9's kernel clock CK_INT (APB2 timers at 96 MHz).
pub const TIMER_HZ: u32 = crate::clocks::CLOCKS.apb2_timer_hz();
/// The update interrupt's vector (TIM9 shares TIM1's break vector).
pub const IRQ: &str = "TIM1_BRK_TIM9";
/// Pins: A, B (alternate function `AF`), index (GPIO output).
pub const PIN_A: &str = "PA2";
pub const PIN_B: &str = "PA3";
pub const PIN_INDEX: &str = "PA4";
pub const AF: u8 = 3;

/// Counter ticks from a period's update event to its first edge.
pub const LEAD: u16 = 1;
/// Fewest cycles from an update event to the interrupt's first store.
pub const ENTRY_MIN: u32 = 12;
/// Most cycles from an update event to the interrupt's index write.
pub const LATENCY_MAX: u32 = 7_500;
/// Slack each side of the index edge.
pub const MARGIN: u32 = 8;
/// Largest prescaler: the first edge precedes the index write.
pub const PSC_MAX: u16 = (ENTRY_MIN - MARGIN) as u16 / LEAD - 1;
/// Shortest half period, cycles: the index write precedes the second edge.
pub const HALF_MIN_CLOCKS: u32 = LATENCY_MAX + MARGIN;
/// Fastest count rate, counts per second.
pub const MAX_COUNT_RATE: u32 = TIMER_HZ / HALF_MIN_CLOCKS;

/// Where the generator is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Running,
    /// OPM set: the counter stops at the next update event.
    Finishing,
    Done,
}

/// The interrupt's side: which period runs, what comes next, the books.
#[derive(Clone, Debug)]
pub struct Generator<I> {
    periods: core::iter::Fuse<I>,
    current: Period,
    last_moving: Option<Period>,
    ledger: Ledger,
    state: State,
    /// found ahead by `prepare` (it divides): the index level for
    /// `current` and the period after it (`None`: the profile ends)
    prepared: bool,
    index: bool,
    next: Option<Period>,
    /// the worst update-to-index-write time seen, CK_INT cycles
    worst_latency: u32,
}

/// What the interrupt applies at one update event.
pub type UpdateOps = heapless::Vec<Op, 6>;

impl<I: Iterator<Item = Period>> Generator<I> {
    /// The generator and the program that starts TIM9 on the first period
    /// (from TIM9 stopped, outputs low); `None` for an empty profile.
    pub fn start(profile: &Profile<'_>, periods: I) -> Option<(Generator<I>, [Op; 15])> {
        let mut periods = periods.fuse();
        let first = periods.next()?;
        let ledger = Ledger::new(profile.cpr());
        let mut gen = Generator {
            periods,
            current: first,
            last_moving: None,
            ledger,
            state: State::Running,
            prepared: false,
            index: false,
            next: None,
            worst_latency: 0,
        };
        gen.prepare();
        Some((gen, program::init(&first)))
    }

    /// The work for the next update event, done after this one's writes
    /// (the handler calls it last): the next period (64- and 128-bit
    /// divisions, hundreds of cycles) and the index level, so that at the
    /// update event the writes come first and nothing divides before them.
    pub fn prepare(&mut self) {
        if self.state != State::Running || self.prepared {
            return;
        }
        self.index = self.ledger.index_in(&self.current);
        self.next = self.periods.next();
        self.prepared = true;
    }

    /// The prepared period after `current` (prepared now if the handler
    /// did not: the slow path, correct but late).
    fn take_next(&mut self) -> Option<Period> {
        self.prepare();
        self.prepared = false;
        self.next.take()
    }

    /// Notes the time from an update event to the index write (the handler
    /// reads TIM9_CNT right after it): the figure `LATENCY_MAX` assumes.
    pub fn note_latency(&mut self, cycles: u32) {
        self.worst_latency = self.worst_latency.max(cycles);
    }

    pub fn worst_latency(&self) -> u32 {
        self.worst_latency
    }

    /// The update interrupt's work, to apply at once: the index level for
    /// the period that just started (first), the flags cleared, then the
    /// next period's values; after the last period the counter is told to
    /// stop at the next update event. If the count would end on A = B = 1
    /// one more period in the last direction brings both low, so a later
    /// start (which forces them low) moves nothing.
    pub fn on_update(&mut self) -> UpdateOps {
        let mut ops = UpdateOps::new();
        match self.state {
            State::Running => {
                let p = self.current;
                let _ = ops.push(self.index_op());
                let _ = ops.push(program::CLEAR_FLAGS);
                let next = self.take_next();
                self.ledger.book(&p);
                if p.motion != Motion::Idle {
                    self.last_moving = Some(p);
                }
                match next.or_else(|| self.parking()) {
                    Some(n) => {
                        self.current = n;
                        let _ = ops.extend_from_slice(&program::next(&n));
                    }
                    None => {
                        self.state = State::Finishing;
                        let _ = ops.push(program::FINISH);
                    }
                }
            }
            State::Finishing => {
                self.state = State::Done;
                let _ = ops.extend_from_slice(&program::DONE);
            }
            State::Done => {
                let _ = ops.push(program::CLEAR_FLAGS);
            }
        }
        ops
    }

    /// The extra period that leaves A and B low, if the count ends with
    /// both high.
    fn parking(&self) -> Option<Period> {
        (self.ledger.levels() == (true, true)).then_some(self.last_moving).flatten()
    }

    /// The first op `on_update` returns, prepared ahead (`prepare`): the
    /// handler applies it first, so the index edge comes as early as it can.
    pub fn index_op(&self) -> Op {
        match self.state {
            State::Running if self.prepared => program::index(self.index),
            State::Running => program::index(self.ledger.index_in(&self.current)),
            State::Finishing | State::Done => program::index(false),
        }
    }

    pub fn ledger(&self) -> &Ledger {
        &self.ledger
    }

    /// The period running since the last update event, until `on_update`
    /// books it (after the last one: the last period, now stopped).
    pub fn current(&self) -> Period {
        self.current
    }

    /// False once the counter has stopped after the last period.
    pub fn running(&self) -> bool {
        self.state != State::Done
    }
}

#[cfg(test)]
mod tests;
