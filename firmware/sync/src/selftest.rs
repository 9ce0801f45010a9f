//! The bench self-test's judge. The board's TIM9 plays
//! a lathe (`polyturn_firmware::quadgen`) into its own lathe-encoder
//! inputs through jumper wires, and the real gearbox runs against it. The
//! generator keeps exact books: the counts and index pulses it made, and
//! where in the profile it is, all in its own timer's time.
//!
//! At each rest, with the lathe still, everything must be exact:
//! * the counter saw exactly the counts made (TIM3 against TIM9);
//! * the index input saw exactly the pulses made (TIM3_CH3), the last one
//!   latched at exactly the count the generator made it at (n·cpr + 1,
//!   which needs its interrupt within `quadgen::LATENCY_MAX`), and none
//!   slipped (a slip is the `encoder-implausible` fault);
//! * the gear's target is the exact rounding of count × p·M/(q·E),
//!   recomputed at low priority (`Scale::round`, 64/128-bit) against the
//!   tick's adds-and-compares DDA;
//! * the cutter stands on that target: its steps, as TIM2 counted them
//!   from TIM1's output, within half a step of the exact target (the
//!   nearest whole step). A pulse lost or added between the plan and the
//!   output is the `step-output` fault at once.
//!
//! While moving, the worst phase error at constant speed and in the ramps
//! are the figures (the
//! controller's own `ferror` trips beyond its limit), and each hold's steps
//! are reported against the gear's target over the same counts.

pub mod plan;
pub use plan::{Kind, Leg, Plan, LEGS};

use crate::state::{Fault, State};

/// The generator's fastest count rate (`polyturn_firmware::quadgen::
/// MAX_COUNT_RATE`, equal by a firmware test): its index is written by an
/// interrupt, which needs time.
pub const GENERATOR_MAX_COUNT_RATE: u32 = 12_786;
/// The speed of the holds when none is asked for (capped by the limits).
pub const DEFAULT_RPM: u32 = 300;
/// The rests with checks: the profile's legs 0, 4 and 8.
pub const RESTS: [usize; 3] = [0, 4, 8];
/// At rest the cutter must stand within half a step of the exact target.
pub const REST_TOLERANCE_Q16: i64 = crate::q16::HALF;

/// Most rpm the generator plays at `cpr` counts per revolution.
pub const fn generator_max_rpm(cpr: u32) -> u32 {
    (GENERATOR_MAX_COUNT_RATE as u64 * 60 / if cpr == 0 { 1 } else { cpr as u64 }) as u32
}

/// The generator's books, read by the firmware from TIM9's interrupt.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Books {
    /// counts made since the start (signed)
    pub counts: i64,
    /// index pulses made
    pub indexes: u32,
    /// ms into the profile, in the generator's own clock
    pub ms: u32,
    /// false once the generator has played the whole profile and stopped
    pub running: bool,
    /// the count TIM3 must have latched at the last index pulse made
    pub last_index: Option<i64>,
    /// the worst time from an update event to the index write, CK_INT
    /// cycles, as TIM9's counter measured it
    pub latency_cycles: u32,
}

/// What the controller shows at the same moment, relative to the start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Seen {
    pub state: State,
    pub counts: i64,
    pub indexes: u32,
    /// the count latched at the last index pulse seen
    pub last_index: i64,
    /// the phase error, Q16 steps (as `status` reports it)
    pub lag_q16: i64,
    /// exact target − steps counted, Q16 steps
    pub off_q16: i64,
    pub cutter_steps: i64,
    pub target_steps: i64,
    /// the gear's target recomputed exactly from the count (only when a
    /// rest is due, `rest_due`: it divides)
    pub exact_steps: i64,
    /// more than 2 s past the plan's length, by the control tick's count
    pub overdue: bool,
}

/// Why a self-test failed; `rest` is 1..=3.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    Fault(Fault),
    /// `stop`, the STOP key, or a state change from outside
    Stopped,
    /// the generator did not play the profile to its end
    Generator,
    NotSynced {
        rest: u8,
    },
    Counts {
        rest: u8,
        seen: i64,
        made: i64,
    },
    /// the last index latched another count than the generator's: its
    /// interrupt wrote the index late (`quadgen::LATENCY_MAX`)
    IndexLate {
        rest: u8,
        seen: i64,
        made: i64,
    },
    Indexes {
        rest: u8,
        seen: u32,
        made: u32,
    },
    Gear {
        rest: u8,
        target: i64,
        exact: i64,
    },
    Cutter {
        rest: u8,
        off_q16: i64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Running,
    Pass,
    Fail(Failure),
}

/// The figures so far.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Report {
    pub rpm: u32,
    pub total_ms: u32,
    pub at_ms: u32,
    pub leg: Kind,
    pub verdict: Verdict,
    /// rests checked and found exact, of 3
    pub rests: u8,
    /// counts made forward (to rest 2) and backward (rest 2 to 3)
    pub forward: i64,
    pub backward: i64,
    pub indexes: u32,
    /// worst |phase error| at constant speed (the holds) and while the
    /// speed changes (the ramps), Q16 steps
    pub hold_lag_q16: i64,
    pub ramp_lag_q16: i64,
    /// per hold: (steps counted, the gear's target's change)
    pub holds: [(i64, i64); 2],
    /// the generator's worst interrupt latency, cycles (`Books`)
    pub latency_cycles: u32,
}

#[derive(Clone, Copy, Debug)]
pub struct SelfTest {
    plan: Plan,
    report: Report,
    /// (hold, cutter steps, target steps) at the start of the hold running
    hold_start: Option<(usize, i64, i64)>,
}

impl SelfTest {
    pub fn new(plan: Plan) -> SelfTest {
        let report = Report {
            rpm: plan.rpm,
            total_ms: plan.total_ms(),
            at_ms: 0,
            leg: Kind::Rest,
            verdict: Verdict::Running,
            rests: 0,
            forward: 0,
            backward: 0,
            indexes: 0,
            hold_lag_q16: 0,
            ramp_lag_q16: 0,
            holds: [(0, 0); 2],
            latency_cycles: 0,
        };
        SelfTest { plan, report, hold_start: None }
    }

    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    pub fn report(&self) -> Report {
        self.report
    }

    pub fn running(&self) -> bool {
        self.report.verdict == Verdict::Running
    }

    /// Ends a running test from outside (`selftest stop`).
    pub fn stop(&mut self) {
        self.fail(Failure::Stopped);
    }

    fn fail(&mut self, f: Failure) {
        if self.running() {
            self.report.verdict = Verdict::Fail(f);
        }
    }

    /// Judges one sample (low priority, every millisecond or so).
    pub fn sample(&mut self, b: &Books, s: &Seen) {
        if !self.running() {
            return;
        }
        match s.state {
            State::Fault(f) => return self.fail(Failure::Fault(f)),
            State::Engaging | State::Synced => {}
            _ => return self.fail(Failure::Stopped),
        }
        let leg = self.plan.leg_at(b.ms);
        self.report.at_ms = b.ms;
        self.report.latency_cycles = b.latency_cycles;
        self.report.leg = self.plan.legs[leg].kind;
        let lag = s.lag_q16.abs();
        match self.report.leg {
            Kind::Hold => self.report.hold_lag_q16 = self.report.hold_lag_q16.max(lag),
            Kind::Ramp => self.report.ramp_lag_q16 = self.report.ramp_lag_q16.max(lag),
            Kind::Rest => {}
        }
        self.holds(leg, s);
        if self.rest_due(b) {
            self.check_rest(self.report.rests + 1, b, s);
        } else if !b.running || s.overdue {
            self.fail(Failure::Generator);
        }
    }

    /// True when `b` is late enough in the next rest to check it.
    pub fn rest_due(&self, b: &Books) -> bool {
        RESTS
            .get(self.report.rests as usize)
            .is_some_and(|&at| b.ms >= self.plan.end_of(at).saturating_sub(plan::SETTLE_BEFORE_END_MS))
    }

    /// Steps and target over each hold, from its first sample to the first
    /// sample after it.
    fn holds(&mut self, leg: usize, s: &Seen) {
        let hold = |i: usize| [2usize, 6].iter().position(|&h| h == i);
        if let Some((h, cutter, target)) = self.hold_start {
            if hold(leg) != Some(h) {
                self.report.holds[h] = (s.cutter_steps - cutter, s.target_steps - target);
                self.hold_start = None;
            }
        }
        if let (None, Some(h)) = (self.hold_start, hold(leg)) {
            if self.report.holds[h] == (0, 0) {
                self.hold_start = Some((h, s.cutter_steps, s.target_steps));
            }
        }
    }

    fn check_rest(&mut self, rest: u8, b: &Books, s: &Seen) {
        let failure = if s.state != State::Synced {
            Some(Failure::NotSynced { rest })
        } else if s.counts != b.counts {
            Some(Failure::Counts { rest, seen: s.counts, made: b.counts })
        } else if s.indexes != b.indexes {
            Some(Failure::Indexes { rest, seen: s.indexes, made: b.indexes })
        } else if b.last_index.is_some_and(|made| made != s.last_index) {
            Some(Failure::IndexLate { rest, seen: s.last_index, made: b.last_index.unwrap_or(0) })
        } else if s.target_steps != s.exact_steps {
            Some(Failure::Gear { rest, target: s.target_steps, exact: s.exact_steps })
        } else if s.off_q16.abs() > REST_TOLERANCE_Q16 {
            Some(Failure::Cutter { rest, off_q16: s.off_q16 })
        } else {
            None
        };
        if let Some(f) = failure {
            return self.fail(f);
        }
        match rest {
            2 => self.report.forward = b.counts,
            3 => self.report.backward = b.counts - self.report.forward,
            _ => {}
        }
        self.report.indexes = b.indexes;
        self.report.rests = rest;
        if rest as usize == RESTS.len() {
            self.report.verdict = Verdict::Pass;
        }
    }
}

#[cfg(test)]
mod tests;
