//! `divide <divisions>|stop`: the spindle turned by hand to equal
//! divisions of a turn, the cutter off (`controller/divide.rs`). The
//! readout, in its reply and in `status` while dividing, is one line of
//! `name=value` figures (`crate::angle` works them out):
//! `divide=6 division=1 division_deg=60.0 to_deg=0.2 to_counts=1.00
//! within=yes`.

use super::status::Snapshot;
use super::{Command, Outcome};
use crate::config::table::DIVIDE_REFUSAL;
use crate::controller::{Controller, Refusal};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DivideOp {
    /// the number, or none if what was sent is not one
    Start(Option<u32>),
    Report,
    Stop,
}

pub const USAGE: &str = "usage: divide <divisions>|stop";
const NOT_DIVIDING: &str = "not dividing: send divide <divisions> first";

pub(super) fn parse(arg: Option<&str>) -> Command<'static> {
    Command::Divide(match arg {
        None => DivideOp::Report,
        Some("stop") => DivideOp::Stop,
        Some(n) => DivideOp::Start(super::number::unsigned(n)),
    })
}

// (out of line, as the readout's writer: the firmware's console task would
// carry a copy of each where it is called)
#[inline(never)]
pub(super) fn apply(op: DivideOp, ctl: &mut Controller) -> Outcome {
    let readout = match op {
        // whatever is wrong with the number, the range says what is right
        DivideOp::Start(None) => Err(DIVIDE_REFUSAL),
        DivideOp::Start(Some(n)) => ctl.start_divide(n).map_err(Refusal::describe),
        DivideOp::Report => ctl.dividing().map(|_| ()).ok_or(NOT_DIVIDING),
        DivideOp::Stop if ctl.stop_divide().is_some() => return Outcome::Text("ok divide ended"),
        DivideOp::Stop => Err(NOT_DIVIDING),
    };
    match readout {
        Ok(()) => Outcome::Divide(Snapshot::of(ctl)),
        Err(why) => Outcome::Error(why),
    }
}

#[cfg(test)]
mod tests;
