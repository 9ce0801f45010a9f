//! The tick's read of the lathe: TIM3's count and the last timed edge, a few
//! loads (the tick's cost is its budget).
//!
//! The pair is latched by one edge in two timers: TIM3_CCR1 at the edge,
//! TIM5_CCR3 when the compare pulse has crossed to TIM5 (TRGO, ITR1's
//! resynchronisation and IC3's edge detector: a few CK_INT cycles,
//! §13.3.15). So the stamp is read on both sides of the count, and the
//! second stamp at least two APB1 reads (each two PCLK1 cycles, 4 CK_INT,
//! at the least) after the count: if the two stamps agree, no edge reached
//! TIM5 between them, and none that reached TIM3 before the count was read
//! can still be on its way. If they differ an edge came in between: the
//! count and the stamp are read once more the same way, and if the stamp
//! moved again (edges closer than a read, faster than any lathe) the tick
//! goes without.

use super::{off, program::CC1IF, TIM3, TIM5};
use crate::regs::Bus;
use polyturn_sync::edges::EdgeRegs;

/// Whether CCR1 and CCR3 hold an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gate {
    /// no edge timing: the start could not tie the stamps to the ticks
    Off,
    /// timed, but nothing captured since `program::CONFIG` (which cleared
    /// CC1IF): the registers hold no edge
    Waiting,
    /// a capture has happened; from here on the tick reads CCR1 every time,
    /// which clears CC1IF (§13.4.5), so it is not looked at again
    Open,
}

impl Gate {
    /// TIM3_SR as the tick read it, before any read of CCR1 (the tick reads
    /// SR every time for the index's CC3IF). CC1IF is set by a capture and
    /// cleared only by reading CCR1 or writing it 0 (§13.4.5), which nothing
    /// does while the gate waits.
    #[inline(always)]
    pub fn note(&mut self, tim3_sr: u32) {
        if *self == Gate::Waiting && tim3_sr & CC1IF != 0 {
            *self = Gate::Open;
        }
    }
}

#[inline(always)]
fn stamp(bus: &mut impl Bus) -> u16 {
    // TIM5 counts 0..=0xFFFF (embassy's ARR): the low half is all of it
    bus.read(TIM5 + off::CCR3) as u16
}

#[inline(always)]
fn count(bus: &mut impl Bus) -> u16 {
    bus.read(TIM3 + off::CCR1) as u16
}

/// TIM3's count (`TickInput::lathe`) and, once the gate is open, the last
/// timed edge (`TickInput::lathe_edge`): stamp, count, TIM3_CNT (the read
/// the tick needs anyway, here as the spacing), stamp.
#[inline(always)]
pub fn lathe(gate: Gate, bus: &mut impl Bus) -> (u16, Option<EdgeRegs>) {
    if gate != Gate::Open {
        return (bus.read(TIM3 + off::CNT) as u16, None);
    }
    let first = stamp(bus);
    let edge = count(bus);
    let cnt = bus.read(TIM3 + off::CNT) as u16;
    let second = stamp(bus);
    if first == second {
        return (cnt, Some(EdgeRegs { count: edge, stamp: first }));
    }
    (cnt, again(second, bus))
}

/// An edge came between the two stamps: once more, the same way (the count
/// read again only for the spacing).
#[cold]
#[inline(never)]
fn again(second: u16, bus: &mut impl Bus) -> Option<EdgeRegs> {
    let edge = count(bus);
    let _spacing = bus.read(TIM3 + off::CNT);
    let third = stamp(bus);
    (third == second).then_some(EdgeRegs { count: edge, stamp: third })
}
