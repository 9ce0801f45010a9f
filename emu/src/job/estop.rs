//! Scenario (c): the E-stop opens mid-cut, inside a tick (its interrupt pre-empts
//! the tick's). STEP must stop within one pulse width,
//! ENABLE go inactive, the step timer stop, and the fault latch: the LED shows
//! code 4 (`led::fault_code(EStop)`) with the contact open, and still after it
//! closes again (only `clear` on the console ends it). Then `clear`, with the
//! contact opening again inside the tick that re-arms the step output: every
//! output must still be safe after it. Then `clear` and ENGAGE while the lathe
//! still turns: the cutter must land on the first pass's phase (the job's
//! exact-gear check at the end).

use super::{ESTOP, GPIOB, MS};
use crate::machine::Machine;
use polyturn_firmware::stepgen::program::{CCMR1, CCMR1_RUN, TIM1};
use polyturn_stm32_model::addr::off;
use polyturn_stm32_model::PinId;
use polyturn_sync::Config;

pub struct Seen {
    /// cycles from the contact opening (inside a tick) to the last STEP rising
    /// edge after it (0: none; None: the contact never opened)
    pub last_rise_after: Option<u64>,
    /// one pulse width, cycles
    pub pulse: u64,
    /// every output in its safe state 2 ms after
    pub safe: bool,
    /// cycles from the contact opening to the E-stop handler's entry, and to its
    /// write stopping TIM1 (the moment no STEP can rise any more)
    pub handler_after: Option<u64>,
    pub stopped_after: Option<u64>,
    /// the same as `stopped_after` on the bound's clock
    pub stopped_after_bound: Option<u64>,
    pub flashes_open: u32,
    pub flashes_closed: u32,
    /// the console's replies to `clear`, after each opening
    pub cleared: String,
    pub cleared_again: String,
    /// the contact opened again inside the tick that re-arms the step output after
    /// `clear`: every output safe 2 ms later (None: the re-arm never came)
    pub mid_arm: Option<bool>,
}

pub fn open_mid_cut(m: &mut Machine, at_s: f64, cfg: &Config) -> Seen {
    m.run((at_s * 1000.0) as u64 * MS);
    // as a tick begins (its first act clears TIM11's UIF): the whole tick is
    // still to run, and the E-stop must not wait for it
    let t0 = open_at_write(m, (polyturn_stm32_model::addr::TIM11 + off::SR, 0), |_| ());
    m.run(2 * MS);
    let last = t0.map(|t0| last_rise_after(m, t0));
    let safe = m.chip().outputs().safe_all();
    let handler_after = m.chip().probe.exti_entered.zip(t0).map(|(h, t)| h - t);
    let stopped_after = m.chip().probe.step_timer_stopped.zip(t0).map(|(h, t)| h - t);
    let p = &m.chip().probe;
    let stopped_after_bound = p.stopped_bound.zip(p.edge_bound).map(|(s, e)| s - e);
    let flashes_open = flashes(m);
    m.drive(GPIOB, ESTOP, Some(false));
    let flashes_closed = flashes(m);
    // `clear` re-arms the step output at the next tick: the contact opens again
    // inside that tick, right after its first TIM1 write (`program::arm` begins
    // with CCMR1 = CCMR1_RUN), and the rest of the arm must not undo the stop
    let mut cleared = String::new();
    let mid_arm = open_at_write(m, (TIM1 + CCMR1, CCMR1_RUN), |m| cleared = clear(m));
    m.run(2 * MS);
    let mid_arm = mid_arm.map(|_| m.chip().outputs().safe_all());
    m.drive(GPIOB, ESTOP, Some(false));
    m.run(100 * MS);
    let cleared_again = clear(m);
    super::press(m, super::ENGAGE);
    let d = polyturn_sync::derived::Derived::new(cfg, polyturn_sync::Timing::FIRMWARE);
    let pulse = d.steps.pulse as u64;
    Seen {
        last_rise_after: last,
        pulse,
        safe,
        handler_after,
        stopped_after,
        stopped_after_bound,
        flashes_open,
        flashes_closed,
        cleared,
        mid_arm,
        cleared_again,
    }
}

fn clear(m: &mut Machine) -> String {
    crate::usb::scenario::exchange(m, "clear\n").map_or_else(|e| e, |r| r.0)
}

/// Opens the contact right after the image writes `value` to `addr`, from `then`
/// on (for at most 100 ms more); returns when (None: the write never came).
fn open_at_write(m: &mut Machine, (addr, value): (u32, u32), then: impl FnOnce(&mut Machine)) -> Option<u64> {
    let p = &mut m.chip().probe;
    (p.edge_at, p.exti_entered) = (None, None);
    p.trip_on_write = Some((addr, value, (GPIOB, ESTOP, None)));
    then(m);
    for _ in 0..100 {
        if m.chip().probe.edge_at.is_some() {
            break;
        }
        m.run(MS);
    }
    m.chip().probe.trip_on_write = None;
    m.chip().probe.edge_at
}

/// Cycles from `t0` to the last STEP rising edge after it (0: none).
fn last_rise_after(m: &mut Machine, t0: u64) -> u64 {
    let edges = m.chip().mcu.edges();
    edges.iter().filter(|e| e.pin == PinId::Pa8 && e.high && e.cycle >= t0).map(|e| e.cycle - t0).max().unwrap_or(0)
}

/// The blink code PC13 shows: sampled every ms for 6.5 s (two 3 s frames), the
/// flashes between two pauses (the longest runs of one level).
pub(crate) fn flashes(m: &mut Machine) -> u32 {
    let mut runs: Vec<(bool, u32)> = Vec::new();
    for _ in 0..6500 {
        m.run(MS);
        let lit = m.chip().gpio[2].pin_out(13).unwrap_or(true);
        match runs.last_mut() {
            Some((l, n)) if *l == lit => *n += 1,
            _ => runs.push((lit, 1)),
        }
    }
    // pauses are the runs of 600 ms or more; count the short runs of the other
    // level between the first two
    let pauses: Vec<usize> = (0..runs.len()).filter(|&i| runs[i].1 >= 600).collect();
    let (Some(&a), Some(&b)) = (pauses.first(), pauses.get(1)) else { return 0 };
    runs[a + 1..b].iter().filter(|r| r.0 != runs[a].0).count() as u32
}
