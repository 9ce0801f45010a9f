//! The bench self-test's hooks in the controller (`controller::selftest`,
//! kept here with the rest of the self-test): the console starts it (the
//! firmware then starts the generator), the firmware's sampler feeds it
//! the generator's books, and it engages the real gearbox and judges it
//! (`crate::selftest`).

use super::activity::{Activity, Asked};
use super::{Controller, Refusal};
use crate::config::{Config, DriveKind};
use crate::derived::Derived;
use crate::encoder::IndexTracker;
use crate::selftest::{self, plan, Books, Plan, Report, Seen, SelfTest};
use crate::state::State;

/// Why a self-test cannot start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SelfTestRefusal {
    NotIdle,
    LatheTurning,
    NoCutter,
    /// drive=bldc: its position is the follower's, not a count of pulses
    /// the board made, so the rests would judge the command against itself
    NotStepper,
    /// a cam table is fitted: the X axis would follow the played lathe
    CamFitted,
    /// the generator makes whole periods of two counts, and its index
    /// falls between them: cpr even and at least 4
    Cpr(u32),
    /// rpm outside 1..=max (the generator, max-rpm and max-rate)
    Rpm {
        max: u32,
    },
    /// an encoder check runs: the chuck is being turned by hand
    Checking,
    /// dividing: the chuck is being turned by hand
    Dividing,
}

impl SelfTestRefusal {
    /// The self-test's words for the activity rule's refusal
    /// (`Controller::admit`): what runs besides, or the cutter not idle.
    fn from_rule(r: Refusal) -> SelfTestRefusal {
        match r {
            Refusal::Checking => SelfTestRefusal::Checking,
            Refusal::Dividing => SelfTestRefusal::Dividing,
            _ => SelfTestRefusal::NotIdle,
        }
    }
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
    /// Starts a self-test at `rpm` (or the default within the limits):
    /// `plan_selftest` then `start_selftest_planned`, in one go (host).
    pub fn start_selftest(&mut self, rpm: Option<u32>) -> Result<Plan, SelfTestRefusal> {
        let p = plan_selftest(&self.config, &self.d, rpm)?;
        self.start_selftest_planned(p).map(|()| p)
    }

    /// Starts `plan` (made for the settings in force): engages at rest and
    /// waits for the generator's books. Short: the tick's lock holds it.
    pub fn start_selftest_planned(&mut self, plan: Plan) -> Result<(), SelfTestRefusal> {
        // before anything changes: a refusal leaves the index as it was
        self.admit(Asked::SelfTest).map_err(SelfTestRefusal::from_rule)?;
        if !self.lathe_at_rest() {
            return Err(SelfTestRefusal::LatheTurning);
        }
        if self.x.is_some() {
            return Err(SelfTestRefusal::CamFitted);
        }
        let ever_engaged = self.ever_engaged;
        // the generator's index is a new reference: the lathe's, if any,
        // is forgotten (and again at the end, `end_selftest`)
        self.index = IndexTracker::default();
        self.engage().map_err(|_| SelfTestRefusal::NotIdle)?;
        let id = self.selftest_last.map_or(0, |r| r.id.wrapping_add(1));
        let run = Run {
            id,
            test: SelfTest::new(plan),
            counts: self.lathe.position(),
            indexes: self.index_seen,
            deadline: self.ticks + (plan.total_ms() as u64 + 2_000) * self.timing.tick_hz as u64 / 1_000,
            ever_engaged,
        };
        self.activity = Activity::SelfTest(run);
        Ok(())
    }

    /// The running self-test.
    fn selftest_run(&self) -> Option<Run> {
        match self.activity {
            // (only while it runs: its end ends the activity, `end_selftest`)
            Activity::SelfTest(r) => Some(r),
            _ => None,
        }
    }

    /// True while a self-test runs: the firmware keeps its generator going.
    pub fn selftest_running(&self) -> bool {
        self.selftest_run().is_some()
    }

    /// The running self-test's number and plan: the firmware plays it.
    pub fn selftest_plan(&self) -> Option<(u32, Plan)> {
        self.selftest_run().map(|r| (r.id, *r.test.plan()))
    }

    /// The figures of the running or last self-test.
    pub fn selftest_report(&self) -> Option<Report> {
        self.selftest_run().or(self.selftest_last).map(|r| r.test.report())
    }

    /// Ends a running self-test (`selftest stop`): ramps the cutter down.
    pub fn stop_selftest(&mut self) -> Option<Report> {
        if let Some(mut run) = self.selftest_run() {
            run.test.stop();
            self.end_selftest(run);
        }
        self.selftest_report()
    }

    /// Judges the generator's `books` against what the controller shows
    /// now, in one go (host tests and the fake board; the firmware splits
    /// it around its lock: `selftest_pending`, `Pending::judge`,
    /// `selftest_judged`).
    pub fn selftest_books(&mut self, books: &Books) {
        if let Some(mut p) = self.selftest_pending() {
            p.judge(books);
            self.selftest_judged(p);
        }
    }

    /// Under the tick's lock: copies of the running test and of what the
    /// controller shows, nothing more (the judging divides and formats
    /// nothing, but it is not short: it runs outside the lock).
    pub fn selftest_pending(&self) -> Option<Pending> {
        let run = self.selftest_run()?;
        let st = self.status();
        let raw = Raw {
            state: self.state,
            lathe: self.lathe.position(),
            origin: self.origin,
            index_seen: self.index_seen,
            last_index: self.last_index,
            lag_q16: st.phase_error_q16,
            off_q16: self.target - (st.cutter_steps << 16),
            cutter_steps: st.cutter_steps,
            target_steps: st.target_steps,
            overdue: self.ticks > run.deadline,
            scale: self.d.scale,
            sense_positive: self.d.sense_positive,
        };
        Some(Pending { run, raw })
    }

    /// Under the tick's lock: keeps the judged run, unless the test ended
    /// meanwhile (`selftest stop`); ends it if the judge did.
    pub fn selftest_judged(&mut self, p: Pending) {
        let current = self.selftest_run().filter(|r| r.id == p.run.id);
        if current.is_none() {
            return;
        }
        if p.run.test.running() {
            self.activity = Activity::SelfTest(p.run);
        } else {
            self.end_selftest(p.run);
        }
    }

    /// The end, whatever it was: the cutter ramps down, and the
    /// generator's index is forgotten as a phase reference.
    fn end_selftest(&mut self, run: Run) {
        self.activity = Activity::None;
        self.selftest_last = Some(run);
        self.disengage();
        self.index = IndexTracker::default();
        self.rebase_pending = false;
        self.ever_engaged = run.ever_engaged;
    }
}

/// The fastest hold the limits allow: the generator's, `max-rpm`, and the
/// motor's `max-rate` with the engage margin (1/16) and more.
pub fn selftest_max_rpm(c: &Config, d: &Derived) -> u32 {
    let s = d.scale;
    // rpm × cpr/60 × num/den ≤ 7/8 max-rate
    let motor = c.max_step_rate_hz as u128 * 7 * 60 * s.den as u128
        / (8 * c.encoder_counts_per_rev.max(1) as u128 * s.num.max(1) as u128);
    let motor = motor.min(u32::MAX as u128) as u32;
    selftest::generator_max_rpm(c.encoder_counts_per_rev).min(c.max_lathe_rpm).min(motor)
}

/// The plan for a self-test at `rpm` (or the default within the limits)
/// under settings `c`: the checks that depend on the settings only. Low
/// priority, outside the tick's lock: it divides in 128 bits.
pub fn plan_selftest(c: &Config, d: &Derived, rpm: Option<u32>) -> Result<Plan, SelfTestRefusal> {
    match c.drive {
        DriveKind::None => return Err(SelfTestRefusal::NoCutter),
        DriveKind::Bldc => return Err(SelfTestRefusal::NotStepper),
        DriveKind::Stepper => {}
    }
    let cpr = c.encoder_counts_per_rev;
    if cpr < 4 || !cpr.is_multiple_of(2) {
        return Err(SelfTestRefusal::Cpr(cpr));
    }
    let max = selftest_max_rpm(c, d);
    let rpm = rpm.unwrap_or(selftest::DEFAULT_RPM.min(max));
    if rpm == 0 || rpm > max {
        return Err(SelfTestRefusal::Rpm { max });
    }
    let rate = plan::rate_hz(rpm, cpr, d.scale.num, d.scale.den);
    Ok(Plan::new(rpm, cpr, plan::ramp_ms(rate, c.max_accel_steps_per_s2)))
}

/// What the controller showed, copied under the lock.
#[derive(Clone, Copy, Debug)]
struct Raw {
    state: State,
    lathe: i64,
    origin: i64,
    index_seen: u32,
    last_index: i64,
    lag_q16: i64,
    off_q16: i64,
    cutter_steps: i64,
    target_steps: i64,
    overdue: bool,
    scale: crate::gear::Scale,
    sense_positive: bool,
}

/// A running test and a copy of what the controller showed, to judge
/// outside the tick's lock.
#[derive(Clone, Copy, Debug)]
pub struct Pending {
    run: Run,
    raw: Raw,
}

impl Pending {
    /// Judges the copy against the generator's `books`; the exact target
    /// (a division) only when a rest is due.
    pub fn judge(&mut self, books: &Books) {
        let (r, run) = (&self.raw, &self.run);
        let exact = if run.test.rest_due(books) {
            let rel = r.lathe - r.origin;
            r.scale.round(if r.sense_positive { rel } else { -rel })
        } else {
            r.target_steps
        };
        let seen = Seen {
            state: r.state,
            counts: r.lathe - run.counts,
            indexes: r.index_seen.wrapping_sub(run.indexes),
            last_index: r.last_index - run.counts,
            lag_q16: r.lag_q16,
            off_q16: r.off_q16,
            cutter_steps: r.cutter_steps,
            target_steps: r.target_steps,
            exact_steps: exact,
            overdue: r.overdue,
        };
        self.run.test.sample(books, &seen);
    }
}
