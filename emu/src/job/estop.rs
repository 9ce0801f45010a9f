//! Scenario (c): the E-stop opens mid-cut. STEP must stop within one pulse width,
//! ENABLE go inactive, the step timer stop, and the fault latch: the LED shows
//! code 4 (`led::fault_code(EStop)`) with the contact open, and still after it
//! closes again (only `clear` on the console ends it). Then `clear` on the console
//! and ENGAGE while the lathe still turns: the cutter must land on the first
//! pass's phase (the job's exact-gear check at the end).

use super::{ESTOP, GPIOB, MS};
use crate::machine::Machine;
use polyturn_stm32_model::PinId;
use polyturn_sync::Config;

pub struct Seen {
    /// cycles from the contact opening to the last STEP rising edge after it (0: none)
    pub last_rise_after: u64,
    /// one pulse width, cycles
    pub pulse: u64,
    /// every output in its safe state 2 ms after
    pub safe: bool,
    /// cycles from the contact opening to the E-stop handler's entry
    pub handler_after: Option<u64>,
    pub flashes_open: u32,
    pub flashes_closed: u32,
    /// the console's reply to `clear`
    pub cleared: String,
}

pub fn open_mid_cut(m: &mut Machine, at_s: f64, cfg: &Config) -> Seen {
    m.run((at_s * 1000.0) as u64 * MS);
    let t0 = m.chip().now;
    m.chip().probe.exti_entered = None;
    m.drive(GPIOB, ESTOP, None); // the contact opens: the pull-up takes PB14 high
    m.run(2 * MS);
    let last = m
        .chip()
        .mcu
        .edges()
        .iter()
        .filter(|e| e.pin == PinId::Pa8 && e.high && e.cycle >= t0)
        .map(|e| e.cycle - t0)
        .max();
    let safe = m.chip().outputs().safe_all();
    let handler_after = m.chip().probe.exti_entered.map(|t| t - t0);
    let flashes_open = flashes(m);
    m.drive(GPIOB, ESTOP, Some(false));
    let flashes_closed = flashes(m);
    let cleared = crate::usb::scenario::exchange(m, "clear\n").map_or_else(|e| e, |r| r.0);
    super::press(m, super::ENGAGE);
    let d = polyturn_sync::derived::Derived::new(cfg, polyturn_sync::Timing::FIRMWARE);
    Seen {
        last_rise_after: last.unwrap_or(0),
        pulse: d.steps.pulse as u64,
        safe,
        handler_after,
        flashes_open,
        flashes_closed,
        cleared,
    }
}

/// The blink code PC13 shows: sampled every ms for 6.5 s (two 3 s frames), the
/// flashes between two pauses (the longest runs of one level).
fn flashes(m: &mut Machine) -> u32 {
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
