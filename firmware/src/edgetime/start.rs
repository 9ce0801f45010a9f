//! What ties the edge registers to the core's ticks, measured once before
//! the first tick (`app::tick::start`, under the tick's lock):
//!
//! * the count in state (A, B) = (0, 0) (`low_low`), from TIM3's count and
//!   the A and B pins read together;
//! * the stamp of the first tick's instant (`start_tick`): TIM11 (PSC 0,
//!   ARR a tick's cycles less one, CNT 0) is started right after TIM5's
//!   count turns to a new value S, so its first update, the first tick's
//!   instant, is a tick (`TICK_CYCLES`) = `STAMPS_PER_TICK` stamps later,
//!   at S + `STAMPS_PER_TICK` (within the few cycles between TIM5's step
//!   and the CEN write, a fraction of a stamp);
//! * after ticks were lost (a flash erase stalls the CPU, and the core drops
//!   its edge clock), the stamp of the next tick the core runs
//!   (`next_instant`), with TIM11 running: both timers count the same
//!   clock, so its updates stay those few cycles after a step of TIM5.
//!
//! Every loop here is bounded; where a measurement fails the tick still
//! starts, without edge times (the boot log says why).

use super::{off, A_PIN, B_PIN, GPIOA_IDR, TIM11, TIM3, TIM5};
use crate::regs::{apply, Bus, Op};
use polyturn_regs::bits::{cr1, sr};
use polyturn_sync::edges::EdgeClock;

/// Tries at reading TIM3's count and the pins with the lathe between counts.
pub const PARITY_TRIES: u32 = 16;
/// CK_INT cycles between the pin read and the count read after it: more
/// than TIM3's input path (§13.3.5: resynchronisation, then the 8-sample
/// filter of `program`, then the edge detector: about 12 cycles by our
/// reading, which the manual gives no figure for), so an
/// edge the pins already show has reached the count by then.
pub const FILTER_WAIT_CYCLES: u32 = 32;
/// Reads of TIM5_CNT waiting for it to step (it steps every 96 cycles, a
/// read takes at least 4, so 24 reads cover a step): a bound, not a
/// figure; at 4 cycles a read it is 8 µs, longer if the bus is slower.
pub const SPIN_READS: u32 = 200;
/// Tries at starting TIM11 within the stamp it was timed to.
pub const SYNC_TRIES: u32 = 4;

/// TIM11 started (TIM11_CR1, §14.5.1: CEN alone, as the tick's timer runs).
pub const TICK_START: Op = Op::Write(TIM11 + off::CR1, cr1::CEN.mask());
/// TIM11 stopped and rewound, its update flag cleared (§14.5.1, §14.5.3):
/// as before `TICK_START`, for another try.
pub const TICK_REWIND: [Op; 3] =
    [Op::Write(TIM11 + off::CR1, 0), Op::Write(TIM11 + off::CNT, 0), Op::Write(TIM11 + off::SR, 0)];

/// A count of state (A, B) = (0, 0), k0 (`EdgeClock::low_low_odd` is its
/// parity; the bench's log shows CCR1 − k0), or `None` if the count moved
/// at every try. Each try reads the count, the pins, and (after
/// `FILTER_WAIT_CYCLES`) both again and the count a third time: equal
/// counts around each pin read mean the pins showed that count's state (an
/// edge the pins show reaches the count within the wait), and two equal pin
/// reads rule out a bounce back and forth between them.
pub fn low_low(bus: &mut impl Bus) -> Option<u16> {
    (0..PARITY_TRIES).find_map(|_| {
        let count = bus.read(TIM3 + off::CNT) as u16;
        let first = bus.read(GPIOA_IDR);
        bus.delay(FILTER_WAIT_CYCLES);
        let again = bus.read(TIM3 + off::CNT) as u16;
        let second = bus.read(GPIOA_IDR);
        bus.delay(FILTER_WAIT_CYCLES);
        let last = bus.read(TIM3 + off::CNT) as u16;
        let still = count == again && again == last && ab(first) == ab(second);
        still.then(|| count.wrapping_sub(place(ab(first))))
    })
}

/// A's and B's levels in GPIOA_IDR.
fn ab(idr: u32) -> (bool, bool) {
    (idr >> A_PIN & 1 == 1, idr >> B_PIN & 1 == 1)
}

/// A state's place in the cycle TIM3 counts up through (§13.3.12 Table 53:
/// (0,0) → (1,0) → (1,1) → (0,1)).
pub fn place((a, b): (bool, bool)) -> u16 {
    match (a, b) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

/// TIM5_CNT's next value, or `None` if it does not step within `SPIN_READS`.
fn next_stamp(bus: &mut impl Bus) -> Option<u16> {
    let from = bus.read(TIM5 + off::CNT) as u16;
    (0..SPIN_READS).map(|_| bus.read(TIM5 + off::CNT) as u16).find(|&s| s != from)
}

/// Starts the tick's timer (TIM11, set up but stopped) right after TIM5
/// steps to S, and returns S; TIM5 read again after the start must still be
/// S, or something (the E-stop's interrupt, the only one the lock lets
/// through) came between, and TIM11 is rewound for another try. `None`: no
/// try worked, and TIM11 runs all the same (the tick must), untimed.
pub fn start_tick(bus: &mut impl Bus) -> Option<u16> {
    for _ in 0..SYNC_TRIES {
        let Some(s) = next_stamp(bus) else { break };
        let _ = apply(&[TICK_START], bus);
        if bus.read(TIM5 + off::CNT) as u16 == s {
            return Some(s);
        }
        let _ = apply(&TICK_REWIND, bus);
    }
    let _ = apply(&[TICK_START], bus);
    None
}

/// TIM11's and TIM5's cycles: a tick (4 800 at 20 kHz) and a stamp (96).
pub(super) const TICK_CYCLES: u32 = crate::clocks::CLOCKS.apb2_timer_hz() / crate::board::TICK_HZ;
pub(super) const STAMP_CYCLES: u32 = super::TIM5_CLOCK_HZ / super::STAMP_HZ;
/// TIM11_SR.UIF (§14.5.3): an update the tick has not answered yet.
const UIF: u32 = sr::UIF.mask();

/// The stamp of the instant of the next tick the core runs, TIM11 running
/// (under the tick's lock: no tick comes in between). Right after TIM5
/// steps to S, TIM11's count c says its next update is `TICK_CYCLES` − c
/// cycles on, which rounds to a whole number of stamps (the updates trail
/// TIM5's steps by the few cycles `start_tick` left, the reads by a few
/// more): S plus that. If UIF is set, a tick is pending, for the update
/// before: `STAMPS_PER_TICK` less.
/// TIM11's count read on both sides of UIF, and TIM5's again, tell an
/// update or a stamp that came in between: another try; `None` after
/// `SYNC_TRIES`, or if TIM5 does not step.
pub fn next_instant(bus: &mut impl Bus) -> Option<u16> {
    for _ in 0..SYNC_TRIES {
        let s = next_stamp(bus)?;
        let count = bus.read(TIM11 + off::CNT);
        let pending = bus.read(TIM11 + off::SR) & UIF != 0;
        let again = bus.read(TIM11 + off::CNT);
        if again < count || bus.read(TIM5 + off::CNT) as u16 != s || count >= TICK_CYCLES {
            continue;
        }
        let stamps = ((TICK_CYCLES - count + STAMP_CYCLES / 2) / STAMP_CYCLES) as u16;
        let next = s.wrapping_add(stamps);
        return Some(if pending { next.wrapping_sub(super::STAMPS_PER_TICK) } else { next });
    }
    None
}

/// The clock for `Controller::start_edges`, from the two measurements: the
/// stamp `start_tick` returned and the count `low_low` found.
pub fn clock(s: u16, low_low: u16) -> EdgeClock {
    restarted(s.wrapping_add(super::STAMPS_PER_TICK), low_low)
}

/// The clock for `Controller::start_edges` from the first instant itself
/// (`next_instant`) and the count `low_low` found.
pub fn restarted(first_instant: u16, low_low: u16) -> EdgeClock {
    let low_low_odd = EdgeClock::low_low_odd(low_low, false, false);
    EdgeClock { first_instant, stamps_per_tick: super::STAMPS_PER_TICK, low_low_odd }
}
