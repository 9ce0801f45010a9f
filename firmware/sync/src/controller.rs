//! The controller: one `tick` per control interrupt (integer adds,
//! multiplies and compares; no 64-bit division, no float) and commands from
//! lower priority. The same code runs in the firmware and the simulator.

use crate::cam::Cam;
use crate::config::{Config, DriveKind};
use crate::derived::Derived;
use crate::drive::Bldc;
use crate::encoder::{Extender, IndexEvent, IndexTracker};
use crate::estimator::Estimator;
use crate::follower::Follower;
use crate::follower::Limits;
use crate::gear::Gear;
use crate::state::{Fault, State};
use crate::steps::pipe::StepPipe;
use crate::steps::StepBook;
use crate::steps::StepPlan;
use crate::timing::Timing;

/// What the hardware reports at the start of a tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TickInput {
    /// lathe encoder timer counter
    pub lathe: u16,
    /// counter value latched at an index pulse since the last tick
    pub index: Option<u16>,
    /// step pulses emitted (free-running 16-bit count), stepper mode
    pub emitted: u16,
    /// cutter encoder timer counter, BLDC mode
    pub cutter: u16,
    pub estop_open: bool,
    pub alarm: bool,
    /// X-axis step pulses emitted (free-running 16-bit count), if fitted
    pub x_emitted: u16,
    /// the lathe encoder's last timed edge, on a board that times them
    /// (`edges`); `None`: the count alone
    pub lathe_edge: Option<crate::edges::EdgeRegs>,
}

/// An X axis (cross-slide) driven by the electronic cam.
#[derive(Clone, Debug)]
pub struct XAxis {
    pub cam: Cam,
    pub limits: Limits,
    follower: Follower,
    last_target: i64,
    /// on its cam: within half a step and matching its speed
    on_cam: bool,
}

impl XAxis {
    pub fn new(cam: Cam, limits: Limits) -> XAxis {
        XAxis { cam, limits, follower: Follower::default(), last_target: 0, on_cam: false }
    }
    /// The commanded X position, Q16 steps.
    pub fn position_q16(&self) -> i64 {
        self.follower.position
    }
}

/// What the hardware does until the next tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TickOutput {
    /// logical enable (the firmware applies the configured polarity)
    pub enable: bool,
    /// stop step output at once
    pub halt: bool,
    pub plan: StepPlan,
    /// BLDC speed command, Q16 cutter counts per tick
    pub speed_q16: i32,
    /// X-axis steps for the next tick
    pub x_plan: StepPlan,
}

/// Why a command was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Refusal {
    Faulted,
    NotIdle,
    Overspeed,
    Busy,
    /// a jog is running
    Moving,
    /// jog refused: the lathe turns
    LatheTurning,
    /// jog refused: drive=none
    NoCutter,
    /// jog refused: under one step, or over ten turns
    JogRange,
    /// encoder check refused: the cutter is engaged or ramping down
    CutterRunning,
    /// encoder check refused: a self-test plays into the lathe input
    SelfTesting,
    /// engage refused: an encoder check runs, the chuck turned by hand
    Checking,
    /// engage refused: drive=none and no cam table, so nothing would move
    NothingToDrive,
    /// jog refused: the cutter is engaged or ramping down
    Engaged,
    /// dividing: the cutter stays off, the chuck is turned by hand
    Dividing,
    /// divide refused: the cutter is engaged or ramping down
    CutterOn,
    /// divide refused: the number of divisions out of range
    DivideRange,
    /// dfu refused: the cutter is not idle, or a fault is latched
    DfuNotIdle,
    /// ratio, edges, dir or drive refused: a cam table is fitted for this cutter
    CamFitted,
}

impl Refusal {
    pub fn describe(self) -> &'static str {
        match self {
            Refusal::Faulted => "a fault is latched: clear it first",
            Refusal::NotIdle => "stop first: settings change only while idle",
            Refusal::Overspeed => "lathe too fast for this ratio: the motor would exceed max-rate",
            Refusal::Busy => "already engaged",
            Refusal::Moving => "a jog is running: wait for it to end, or stop",
            Refusal::LatheTurning => "stop the lathe first: jog only with the lathe at rest",
            Refusal::NoCutter => "drive=none: there is no cutter to jog",
            Refusal::JogRange => "jog -3600..=3600 degrees of the cutter, at least one step",
            Refusal::CutterRunning => {
                "stop first: the encoder check has the chuck turned by hand, only with the cutter idle"
            }
            Refusal::SelfTesting => "a self-test is running: selftest stop first, then unplug its jumpers",
            Refusal::Checking => {
                "an encoder check is running (the chuck is being turned by hand): check-encoder stop first"
            }
            Refusal::NothingToDrive => {
                "drive=none and no cam table: nothing to engage (set drive stepper or bldc, or upload a cam table)"
            }
            Refusal::Engaged => "stop first: the cutter is engaged or ramping down (jog only while idle)",
            Refusal::Dividing => "dividing (the chuck is turned by hand, the cutter stays off): divide stop first",
            Refusal::CutterOn => "stop first: the cutter is engaged or ramping down (divide only while idle)",
            Refusal::DivideRange => crate::config::table::DIVIDE_REFUSAL,
            Refusal::DfuNotIdle => "stop first (and clear any fault): dfu restarts the board into its ROM bootloader",
            Refusal::CamFitted => {
                "a cam table is fitted for this cutter (ratio, edges, dir, drive): cam off first (polyturn device cam-off), then upload a table made for the new one"
            }
        }
    }
}

pub struct Controller {
    config: Config,
    d: Derived,
    timing: Timing,
    state: State,
    lathe: Extender,
    index: IndexTracker,
    gear: Gear,
    est: Estimator,
    follower: Follower,
    steps: StepPipe,
    bldc: Bldc,
    /// target at the last tick's end, Q16 steps, and its speed
    target: i64,
    target_velocity: i64,
    ever_engaged: bool,
    rebase_pending: bool,
    origin: i64,
    /// whole cutter turns dropped at engagement, in steps (a multiple of M)
    turns: i64,
    x: Option<XAxis>,
    /// Where the X axis really is: its pulses, each the way of the plan
    /// that made it. The controller's, not a cam's: the cross-slide stays
    /// where the last cam left it when another is fitted, and the pulse
    /// counter (never reset) has counted every move, both ways.
    x_steps: StepBook,
    ticks: u64,
    /// set while a flash write stalls the CPU (`stall`)
    stall: Option<stall::Watch>,
    config_generation: u32,
    /// index edges seen (wraps) and the count latched at the last one,
    /// for the encoder check (kept by the tick: one add, one copy)
    index_seen: u32,
    last_index: i64,
    /// the jog, encoder check, self-test or dividing running (`activity`)
    activity: activity::Activity,
    /// the last self-test's run, once it has ended
    selftest_last: Option<selftest::Run>,
    /// the shaft encoder against the books (`lost`)
    lost: lost::LostSteps,
    /// the lathe's edge times, once the board has said how they line up
    edges: Option<crate::edges::EdgeTimer>,
    /// `control` left a step plan to make (`plan_steps`)
    plan_due: bool,
}

impl Controller {
    pub fn new(config: Config, timing: Timing) -> Controller {
        let d = Derived::new(&config, timing);
        Controller {
            config,
            d,
            timing,
            state: State::Idle,
            lathe: Extender::default(),
            index: IndexTracker::default(),
            gear: Gear::new(d.scale),
            est: Estimator::resting(d.still_ticks),
            follower: Follower::default(),
            steps: StepPipe::default(),
            bldc: Bldc::default(),
            target: 0,
            target_velocity: 0,
            ever_engaged: false,
            rebase_pending: false,
            origin: 0,
            turns: 0,
            x: None,
            x_steps: StepBook::default(),
            ticks: 0,
            stall: None,
            config_generation: 0,
            index_seen: 0,
            last_index: 0,
            activity: activity::Activity::None,
            selftest_last: None,
            lost: lost::LostSteps::default(),
            edges: None,
            plan_due: false,
        }
    }

    /// Latches the first raw readings so the first tick sees no jump.
    pub fn start(&mut self, lathe: u16, emitted: u16, cutter: u16) {
        self.lathe = Extender::new(lathe);
        self.steps.start(emitted);
        self.bldc.start(cutter);
    }

    /// Turns the edge times on (`edges`): the board times A's rising
    /// edges, and `clock` says how its stamps meet the ticks.
    pub fn start_edges(&mut self, clock: crate::edges::EdgeClock) {
        self.edges = Some(crate::edges::EdgeTimer::new(clock));
    }

    /// Turns the edge times off: the board could not measure its clock
    /// again after lost ticks, and a clock known to be off must not place
    /// the lathe (the count alone does until `start_edges`).
    pub fn stop_edges(&mut self) {
        self.edges = None;
    }

    /// Whether the lathe's edge times are in use (off until `start_edges`,
    /// and again after a save's stall lost ticks).
    pub fn edge_timing(&self) -> bool {
        self.edges.is_some()
    }

    /// The control tick: `control`, then the step plan (`plan_steps`).
    pub fn tick(&mut self, io: &TickInput) -> TickOutput {
        let mut out = self.control(io);
        out.plan = self.plan_steps();
        out
    }

    /// The step plan `control` left: the window two ticks on, to where the
    /// follower now is (`steps::pipe`); empty if it left none. The
    /// firmware runs it apart from `control`, one level below the tick
    /// (`app/tick/plan.rs`): the window it fills starts a tick after the next,
    /// so it has a tick's slack the rest has not (grbl plans its segments
    /// outside the step interrupt for the same reason). Nothing but the
    /// plan may come between the two: the plan is this tick's only while
    /// no other tick has run.
    #[inline]
    pub fn plan_steps(&mut self) -> StepPlan {
        if !core::mem::take(&mut self.plan_due) {
            return StepPlan::default();
        }
        self.steps.plan(self.follower.position, &self.d.steps)
    }

    /// The control tick without its step plan (`plan_steps` makes it):
    /// `TickOutput::plan` is empty.
    pub fn control(&mut self, io: &TickInput) -> TickOutput {
        self.ticks += 1;
        let delta = self.lathe.update(io.lathe);
        // (during a flash stall, `stall` judges jumps and indexes)
        let implausible = delta.abs() > self.d.max_counts_per_tick;
        if !self.stall_jump(delta) && implausible {
            self.trip(Fault::EncoderImplausible);
        }
        if let Some(raw) = io.index {
            if !self.stall_index(raw) {
                self.on_index(raw);
            }
        }
        // Bounded once (an implausible jump has tripped above): the gear and
        // the X cam take the bounded count. The estimator takes no count
        // from a jump no lathe can make (a stall's, or a fault's): it is
        // not speed, and a stopped lathe would read thousands of rpm after
        // it.
        let clamped = if implausible { self.bounded_jump(delta) } else { delta };
        let measured = self.measure_lathe(io, implausible);
        let sign = |v: i32| if self.d.sense_positive { v } else { -v };
        self.gear.advance(sign(clamped));
        self.est.update_measured(sign(if implausible { 0 } else { delta }), measured);
        if io.estop_open {
            self.trip(Fault::EStop);
        }
        if io.alarm {
            self.trip(Fault::DriveAlarm);
        }
        let cutter = self.measure(io);
        self.update_target();
        self.step_state(cutter);
        let mut out = self.output(cutter);
        if self.x.is_some() {
            out.x_plan = self.tick_x(io, clamped, out.enable);
        }
        out
    }

    /// The X axis follows the cam while the cutter is engaged, else holds.
    /// Out of line: a lathe without an X axis pays only the call.
    #[inline(never)]
    fn tick_x(&mut self, io: &TickInput, delta: i32, enable: bool) -> StepPlan {
        let Some(x) = &mut self.x else { return StepPlan::default() };
        // The cam is a function of the lathe's angle whatever the sense.
        x.cam.advance(delta);
        let offset = if self.d.sense_positive { self.est.offset_q16() } else { -self.est.offset_q16() };
        let at = self.x_steps.read(io.x_emitted) << 16;
        let target = x.cam.position_q16(offset);
        let velocity = target - x.last_target;
        x.last_target = target;
        if !enable {
            x.follower = Follower { position: at, velocity: 0 };
            self.x_steps.hold(at);
            x.on_cam = false;
            return StepPlan::default();
        }
        match self.state {
            State::Engaging | State::Synced => x.follower.track(target + velocity, velocity, &x.limits),
            _ => x.follower.ramp_down(&x.limits),
        }
        // The axis must really be where it is commanded (its steps can be
        // limited by the step generator), and its command on the cam (an
        // axis whose limits cannot follow the cam falls behind it): the
        // same limit as the cutter's, or the part is cut wrong unsaid.
        x.on_cam = x.follower.arrived(target + velocity, velocity, &x.limits);
        let unmade = x.follower.position - at;
        let behind = target - x.follower.position;
        let plan = self.x_steps.plan(x.follower.position, &self.d.steps);
        let limit = self.d.following_limit_q16;
        if self.state == State::Synced && (unmade.abs() > limit || crate::q16::beyond(behind, limit)) {
            self.trip(Fault::FollowingError);
        }
        plan
    }

    /// The lathe's position from its last timed edge, as an offset from
    /// the count in the core's sense (`edges`); none without edge times,
    /// or on a jump no lathe makes.
    #[inline]
    fn measure_lathe(&mut self, io: &TickInput, implausible: bool) -> Option<i64> {
        let m = self.edges.as_mut()?.measure(io.lathe_edge, &self.lathe);
        let m = if implausible { None } else { m }?;
        Some(if self.d.sense_positive { m } else { -m })
    }

    fn on_index(&mut self, raw: u16) {
        let pos = self.lathe.position_of(raw);
        self.index_seen = self.index_seen.wrapping_add(1);
        self.last_index = pos;
        match self.index.on_index(pos, self.config.encoder_counts_per_rev as i64, 2) {
            IndexEvent::Referenced(_) => self.rebase_pending = !self.ever_engaged,
            IndexEvent::Consistent => {}
            IndexEvent::Slipped(_) => self.trip(Fault::EncoderImplausible),
        }
    }

    /// The cutter's position in Q16 steps: emitted steps, or its encoder.
    fn measure(&mut self, io: &TickInput) -> i64 {
        match self.config.drive {
            DriveKind::Stepper => {
                if matches!(self.state, State::Fault(f) if f.immediate()) {
                    self.steps.halted(io.emitted);
                } else if !self.steps.check(io.emitted) {
                    self.trip(Fault::StepOutput);
                    self.steps.halted(io.emitted);
                }
                self.check_lost_steps(io.cutter);
                self.steps.position() << 16
            }
            DriveKind::Bldc => self.bldc.read(io.cutter) << 16,
            // nothing to measure: the (unused) gear follows itself
            DriveKind::None => self.follower.position,
        }
    }

    /// Ticks from the encoder reading to the end of the window that this
    /// tick's output fills (`Derived::ahead_ticks`: worked out once, a load
    /// in the tick).
    #[inline(always)]
    pub(crate) fn ahead(&self) -> i64 {
        self.d.ahead_ticks
    }

    /// Exact rounded gear target + rounding remainder + sub-count
    /// interpolation + phase offset, predicted to the end of the window this
    /// tick plans (the stepper's plan runs two ticks later: `steps::pipe`).
    fn update_target(&mut self) {
        let d = &self.d;
        let exact = crate::q16::from_steps(self.gear.steps()) + d.remainder_q16(self.gear.rem2());
        let interp = crate::q16::mul(self.est.offset_q16() as i64, d.steps_per_count_q16);
        let limit = (d.max_counts_per_tick as i64) << 16;
        let v_counts = crate::q16::bound(self.est.velocity_q32() >> 16, limit);
        self.target_velocity = crate::q16::mul(v_counts, d.steps_per_count_q16);
        let ahead = self.target_velocity * self.ahead();
        self.target = exact + interp + d.phase_offset_q16 + (self.turns << 16) + ahead;
    }

    fn step_state(&mut self, cutter: i64) {
        // (the limits by reference: a copy is six words a tick)
        match self.state {
            State::Idle => self.follower = Follower { position: cutter, velocity: 0 },
            State::Engaging | State::Synced => {
                if crate::q16::beyond(self.target_velocity, self.d.limits.max_velocity)
                    && self.config.drive != DriveKind::None
                {
                    self.trip(Fault::Overspeed);
                    return self.follower.ramp_down(&self.d.limits);
                }
                self.follower.track(self.target, self.target_velocity, &self.d.limits);
                self.check_sync(cutter);
            }
            State::Disengaging => {
                self.follower.ramp_down(&self.d.limits);
                if self.follower.velocity == 0 {
                    self.state = State::Idle;
                }
            }
            State::Jogging => self.step_jog(cutter),
            State::Fault(f) if f.immediate() => self.follower = Follower { position: cutter, velocity: 0 },
            State::Fault(_) => self.follower.ramp_down(&self.d.limits),
        }
    }

    fn check_sync(&mut self, cutter: i64) {
        if self.state == State::Engaging {
            // with no cutter (drive=none) only the X axis has to arrive
            let none = self.config.drive == DriveKind::None;
            let cutter_on = none || self.follower.arrived(self.target, self.target_velocity, &self.d.limits);
            // synchronised means every axis: an X axis must be on its cam too
            let x_on_cam = self.x.as_ref().is_none_or(|x| x.on_cam);
            if cutter_on && x_on_cam {
                self.state = State::Synced;
            }
            return;
        }
        let lag = match self.config.drive {
            DriveKind::Stepper => self.target - self.follower.position,
            DriveKind::Bldc => self.follower.position - cutter,
            DriveKind::None => 0,
        };
        if crate::q16::beyond(lag, self.d.following_limit_q16) {
            self.trip(Fault::FollowingError);
        }
    }

    /// A jump no lathe makes, bounded to the most a tick can count (out of
    /// line: it never comes on the common path).
    #[cold]
    #[inline(never)]
    fn bounded_jump(&self, delta: i32) -> i32 {
        delta.signum() * self.d.max_counts_per_tick
    }

    /// (ENABLE, halt) in the present state.
    fn enable_and_halt(&self) -> (bool, bool) {
        match self.state {
            State::Engaging | State::Synced | State::Disengaging | State::Jogging => (true, false),
            State::Fault(f) if f.immediate() => (false, true),
            State::Fault(_) => (self.follower.velocity != 0, false),
            State::Idle => (false, false),
        }
    }

    fn output(&mut self, cutter: i64) -> TickOutput {
        let (enable, halt) = self.enable_and_halt();
        let mut out = TickOutput { enable, halt, ..TickOutput::default() };
        if !enable {
            self.bldc.reset();
            self.steps.hold(self.follower.position, &self.d.steps);
            return out;
        }
        match self.config.drive {
            DriveKind::Stepper => self.plan_due = true,
            DriveKind::Bldc => {
                let (cmd, stalled) = self.bldc.command(&self.follower, cutter, &self.d);
                out.speed_q16 = cmd;
                if stalled {
                    self.trip(Fault::Stall);
                }
            }
            DriveKind::None => {}
        }
        out
    }

    /// Latches a fault. The first one is kept until cleared, except that an
    /// immediate fault (E-stop, alarm) always takes over from a ramped one:
    /// an E-stop during a ramp-down must still stop at once.
    pub fn trip(&mut self, f: Fault) {
        if let State::Fault(current) = self.state {
            if current.immediate() || !f.immediate() {
                return;
            }
        }
        // (no log here: the tick calls this, and logging is not for the
        // tick; the firmware's service task logs every change of state)
        self.state = State::Fault(f);
        // a jog ends with its state
        self.end_jog();
    }
}

pub mod activity;
#[cfg(test)]
mod activity_tests;
mod checks;
mod commands;
mod divide;
#[cfg(test)]
mod divide_tests;
#[cfg(test)]
mod edge_tests;
#[cfg(test)]
mod fault_tests;
#[cfg(test)]
mod index_tests;
pub mod jog;
mod lost;
#[cfg(test)]
mod lost_tests;
#[cfg(test)]
mod refusal_tests;
#[cfg(test)]
mod rig;
// the self-test's hooks, with the rest of the self-test (`crate::selftest`)
#[path = "selftest/controller.rs"]
pub mod selftest;
#[cfg(test)]
mod sense_tests;
#[cfg(test)]
mod settings_tests;
#[cfg(test)]
mod setup_tests;
#[cfg(test)]
mod split_tests;
mod stall;
#[cfg(test)]
mod sync_tests;
#[cfg(test)]
mod target_tests;
#[cfg(test)]
mod tracking_tests;
#[cfg(test)]
mod turns_tests;
#[cfg(test)]
mod x_axis_tests;
pub use activity::{Asked, Divide};
pub use commands::{changes_the_cutter, check_table, prepare_cam, PreparedConfig, Status};
pub use jog::JogPlan;
pub use lost::ShaftGap;
pub use stall::Stall;

#[cfg(test)]
mod tests;
