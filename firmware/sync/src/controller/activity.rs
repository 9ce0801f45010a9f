//! What the controller does besides following the lathe: one activity at
//! a time, and the one rule of which may start while another runs. Every
//! refusal of a start (`engage`, `jog`, `check-encoder start`, `selftest
//! start`, `divide`, `dfu`) takes its reason from `Controller::admit`.
//!
//! Why they exclude each other:
//! * a jog turns the cutter: nothing else starts until it ends;
//! * the encoder check and dividing have the chuck turned by hand: no
//!   cutter may move then (but a jog asked for while dividing, with the
//!   lathe at rest, which the machinist sees and stops);
//! * the self-test's generator plays into the lathe input through jumper
//!   wires: no hand on the chuck, no other use of the count.

use super::selftest::Run;
use super::{Controller, Refusal};
use crate::check::EncoderCheck;
use crate::follower::Limits;
use crate::state::State;

/// Dividing a turn (`divide N`): the cutter stays off; `status` shows the
/// spindle against the divisions (`crate::angle`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Divide {
    /// equal divisions of one turn of the spindle
    pub divisions: u32,
}

/// A jog under way (`jog`, `controller::jog`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Jog {
    /// where the cutter ends, Q16 steps (whole steps)
    pub(super) target: i64,
    pub(super) limits: Limits,
    /// the tick by which it must have ended (twice the plan, plus 1 s)
    pub(super) deadline: u64,
    /// the lathe's count at the start: a jog ends if the lathe turns
    pub(super) lathe: i64,
    /// dividing when it was asked for: dividing again once it ends
    pub(super) dividing: Option<Divide>,
}

/// The activity running, if any.
#[derive(Clone, Copy, Debug)]
pub(super) enum Activity {
    None,
    Jog(Jog),
    Check(EncoderCheck),
    /// only while the test runs: its last figures are kept apart
    /// (`Controller::selftest_last`)
    SelfTest(Run),
    Divide(Divide),
}

/// What a command asks to start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Asked {
    Engage,
    Jog,
    Check,
    SelfTest,
    Divide,
    /// the restart into the ROM bootloader (`dfu`)
    Dfu,
}

impl Activity {
    /// Whether `asked` may start while this runs, or why not.
    fn admits(&self, asked: Asked) -> Result<(), Refusal> {
        match (self, asked) {
            (Activity::None, _) => Ok(()),
            (Activity::Jog(_), _) => Err(Refusal::Moving),
            // the check restarts
            (Activity::Check(_), Asked::Check) => Ok(()),
            (Activity::Check(_), _) => Err(Refusal::Checking),
            (Activity::SelfTest(_), _) => Err(Refusal::SelfTesting),
            // a new number of divisions; a jog, the lathe at rest
            (Activity::Divide(_), Asked::Divide | Asked::Jog) => Ok(()),
            (Activity::Divide(_), _) => Err(Refusal::Dividing),
        }
    }
}

/// Whether `asked` may start in the cutter's `state` (a fault aside).
fn state_admits(state: State, asked: Asked) -> Result<(), Refusal> {
    match (asked, state) {
        (_, State::Idle) => Ok(()),
        (Asked::Dfu, _) => Err(Refusal::DfuNotIdle),
        (_, State::Jogging) => Err(Refusal::Moving),
        (Asked::Engage, State::Engaging | State::Synced) => Err(Refusal::Busy),
        (Asked::Engage, _) => Ok(()),
        (Asked::Jog, _) => Err(Refusal::Engaged),
        (Asked::Check, _) => Err(Refusal::CutterRunning),
        (Asked::SelfTest, _) => Err(Refusal::NotIdle),
        (Asked::Divide, _) => Err(Refusal::CutterOn),
    }
}

impl Controller {
    /// The one rule: whether `asked` may start now, or why not. A latched
    /// fault first (`dfu` says it with the cutter's state), then the
    /// activity running, then the cutter's state.
    pub fn admit(&self, asked: Asked) -> Result<(), Refusal> {
        if asked != Asked::Dfu && matches!(self.state, State::Fault(_)) {
            return Err(Refusal::Faulted);
        }
        self.activity.admits(asked)?;
        state_admits(self.state, asked)
    }

    /// A jog ends (done, stopped, knocked or faulted): back to dividing if
    /// it was asked for while dividing, else to nothing. Out of line: the
    /// tick's faults call it, and a jog's end is once a jog.
    #[inline(never)]
    pub(super) fn end_jog(&mut self) {
        if let Activity::Jog(j) = self.activity {
            self.activity = j.dividing.map_or(Activity::None, Activity::Divide);
        }
    }
}
