//! The bench self-test's hooks in the controller (issue 14, part 6): the
//! console starts it (the firmware then starts the generator), the
//! firmware's sampler feeds it the generator's books, and it engages the
//! real gearbox and judges it (`crate::selftest`).

use super::Controller;
use crate::config::DriveKind;
use crate::encoder::IndexTracker;
use crate::selftest::{self, plan, Books, Plan, Report, Seen, SelfTest};
use crate::state::State;

/// Why a self-test cannot start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SelfTestRefusal {
    NotIdle,
    LatheTurning,
    NoCutter,
    /// the generator makes whole periods of two counts, and its index
    /// falls between them: cpr even and at least 4
    Cpr(u32),
    /// rpm outside 1..=max (the generator, max-rpm and max-rate)
    Rpm {
        max: u32,
    },
}

/// The run in progress (or the last one), and what it started from.
#[derive(Clone, Copy, Debug)]
pub(super) struct Run {
    /// one more for each run: the firmware's generator belongs to one
    id: u32,
    test: SelfTest,
    counts: i64,
    indexes: u32,
    /// the tick by which the plan must have played (2 s to spare)
    deadline: u64,
    ever_engaged: bool,
}

impl Controller {
    /// The fastest hold the limits allow: the generator's, `max-rpm`, and
    /// the motor's `max-rate` with the engage margin (1/16) and more.
    pub fn selftest_max_rpm(&self) -> u32 {
        let c = &self.config;
        let s = self.d.scale;
        // rpm × cpr/60 × num/den ≤ 7/8 max-rate
        let motor = c.max_step_rate_hz as u128 * 7 * 60 * s.den as u128
            / (8 * c.encoder_counts_per_rev.max(1) as u128 * s.num.max(1) as u128);
        let motor = motor.min(u32::MAX as u128) as u32;
        selftest::generator_max_rpm(c.encoder_counts_per_rev).min(c.max_lathe_rpm).min(motor)
    }

    /// Starts a self-test at `rpm` (or the default within the limits):
    /// engages at rest and waits for the generator's books. Low priority.
    pub fn start_selftest(&mut self, rpm: Option<u32>) -> Result<Plan, SelfTestRefusal> {
        if self.state != State::Idle {
            return Err(SelfTestRefusal::NotIdle);
        }
        if self.config.drive == DriveKind::None {
            return Err(SelfTestRefusal::NoCutter);
        }
        if !self.lathe_at_rest() {
            return Err(SelfTestRefusal::LatheTurning);
        }
        let cpr = self.config.encoder_counts_per_rev;
        if cpr < 4 || !cpr.is_multiple_of(2) {
            return Err(SelfTestRefusal::Cpr(cpr));
        }
        let max = self.selftest_max_rpm();
        let rpm = rpm.unwrap_or(selftest::DEFAULT_RPM.min(max));
        if rpm == 0 || rpm > max {
            return Err(SelfTestRefusal::Rpm { max });
        }
        let s = self.d.scale;
        let rate = plan::rate_hz(rpm, cpr, s.num, s.den);
        let p = Plan::new(rpm, cpr, plan::ramp_ms(rate, self.config.max_accel_steps_per_s2));
        let ever_engaged = self.ever_engaged;
        // the generator's index is a new reference: the lathe's, if any,
        // is forgotten (and again at the end, `end_selftest`)
        self.index = IndexTracker::default();
        self.engage().map_err(|_| SelfTestRefusal::NotIdle)?;
        let id = self.selftest.map_or(0, |r| r.id.wrapping_add(1));
        let run = Run {
            id,
            test: SelfTest::new(p),
            counts: self.lathe.position(),
            indexes: self.index_seen,
            deadline: self.ticks + (p.total_ms() as u64 + 2_000) * self.timing.tick_hz as u64 / 1_000,
            ever_engaged,
        };
        self.selftest = Some(run);
        Ok(p)
    }

    /// True while a self-test runs: the firmware keeps its generator going.
    pub fn selftest_running(&self) -> bool {
        self.selftest.is_some_and(|r| r.test.running())
    }

    /// The running self-test's number and plan: the firmware plays it.
    pub fn selftest_plan(&self) -> Option<(u32, Plan)> {
        self.selftest.filter(|r| r.test.running()).map(|r| (r.id, *r.test.plan()))
    }

    /// The figures of the running or last self-test.
    pub fn selftest_report(&self) -> Option<Report> {
        self.selftest.map(|r| r.test.report())
    }

    /// Ends a running self-test (`selftest stop`): ramps the cutter down.
    pub fn stop_selftest(&mut self) -> Option<Report> {
        let mut run = self.selftest?;
        if run.test.running() {
            run.test.stop();
            self.end_selftest(run);
        }
        self.selftest_report()
    }

    /// Judges the generator's `books` against what the controller shows
    /// now (the firmware's sampler, low priority, about every ms).
    pub fn selftest_books(&mut self, books: &Books) {
        let Some(mut run) = self.selftest else { return };
        if !run.test.running() {
            return;
        }
        let seen = self.seen(&run, run.test.rest_due(books));
        run.test.sample(books, &seen);
        if run.test.running() {
            self.selftest = Some(run);
        } else {
            self.end_selftest(run);
        }
    }

    /// What the controller shows, copied under the tick's lock: the exact
    /// target (a division) only when a rest is judged, three times a test.
    fn seen(&self, run: &Run, rest: bool) -> Seen {
        let st = self.status();
        let exact = if rest {
            let rel = self.lathe.position() - self.origin;
            self.d.scale.round(if self.d.sense_positive { rel } else { -rel })
        } else {
            st.target_steps
        };
        Seen {
            state: self.state,
            counts: self.lathe.position() - run.counts,
            indexes: self.index_seen.wrapping_sub(run.indexes),
            lag_q16: st.phase_error_q16,
            off_q16: self.target - (st.cutter_steps << 16),
            cutter_steps: st.cutter_steps,
            target_steps: st.target_steps,
            exact_steps: exact,
            overdue: self.ticks > run.deadline,
        }
    }

    /// The end, whatever it was: the cutter ramps down, and the
    /// generator's index is forgotten as a phase reference.
    fn end_selftest(&mut self, run: Run) {
        self.selftest = Some(run);
        self.disengage();
        self.index = IndexTracker::default();
        self.rebase_pending = false;
        self.ever_engaged = run.ever_engaged;
    }
}
