//! The spindle's angle and the division it is at, as words of `status`
//! and of `divide`'s readout.

use super::super::Reply;
use super::Snapshot;
use crate::angle::{Angle, Division};
use core::fmt::Write;

/// The spindle's angle in the snapshot.
fn angle(s: &Snapshot) -> Angle {
    Angle::of(s.status.lathe_counts, s.status.index_counts, s.config.encoder_counts_per_rev)
}

/// ` angle_deg=59.9 angle_from=index|start`
pub(in crate::console) fn write_angle(s: &Snapshot, out: &mut Reply) {
    let a = angle(s);
    let from = if a.from_index { "index" } else { "start" };
    let _ = write!(out, " angle_deg={} angle_from={from}", a.degrees());
}

/// ` divide=6 division=1 division_deg=60.0 to_deg=0.2 to_counts=1.00
/// within=yes`, while dividing.
pub(in crate::console) fn write_division(s: &Snapshot, out: &mut Reply) {
    let Some(n) = s.status.divisions else { return };
    let d = Division::of(&angle(s), n);
    let _ = write!(
        out,
        " divide={n} division={} division_deg={} to_deg={} to_counts={} within={}",
        d.number,
        d.at_degrees(),
        d.to_degrees(),
        d.to_counts(),
        if d.within() { "yes" } else { "no" }
    );
}

/// `ok divide=.. division=.. ... angle_deg=.. angle_from=..`
#[inline(never)]
pub(in crate::console) fn write_readout(s: &Snapshot, out: &mut Reply) {
    let _ = out.push_str("ok");
    write_division(s, out);
    write_angle(s, out);
}
