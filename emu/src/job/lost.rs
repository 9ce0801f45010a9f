//! A lost tick on the real image (`app::tick::check_ticks`,
//! `edgetime::watch`): mid-cut the tick is held off for longer than a tick,
//! as a thread-mode section at its level would hold it (`Chip::
//! tick_held_until`), so TIM11's updates meet one pending interrupt and
//! ticks are lost. The image must count exactly the ticks the emulator saw
//! lost, here and in every other job (no false alarm), and measure its edge
//! clock again. After the late tick the pulses counted no longer fit the
//! step windows the books hold (observed: which window went wrong is not
//! looked at), and the cutter stops with `fault=step-output`, LED code 7.

use super::MS;
use crate::machine::Machine;

/// Ticks lost since boot: the image's count and the emulator's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counted {
    /// `app::tick::TICKS_LOST` (None: no such symbol in the image)
    pub image: Option<u32>,
    /// TIM11 updates less the tick handler's entries, less one still pending
    pub seen: u64,
}

/// The hold, and what the image's edge clock was before it.
#[derive(Clone, Copy, Debug)]
pub struct Held {
    pub hold_us: u64,
    /// TIM11 updates during the hold (the first is answered after it)
    pub updates: u64,
    /// the edge clock's first instant before the hold, and after the job
    pub clock_before: Option<u16>,
    pub clock_after: Option<u16>,
    /// `app::tick::STEPS_LATE` after the hold: step segments the DMA
    /// reached before the tick wrote them (each halts the output)
    pub steps_late: Option<u32>,
    /// the LED's fault code after the job (`led::fault_code`; 0: none)
    pub led_code: u32,
}

impl Held {
    pub fn judged(self, m: &mut Machine) -> Held {
        let clock_after = m.edge_clock().map(|c| c.0.first_instant);
        Held { clock_after, led_code: super::estop::flashes(m), ..self }
    }
}

pub fn hold(m: &mut Machine, at_s: f64, hold_us: u64) -> Held {
    m.run((at_s * 1000.0) as u64 * MS);
    let clock_before = m.edge_clock().map(|c| c.0.first_instant);
    let c = m.chip();
    let before = c.mcu.tim11_updates();
    c.tick_held_until = c.now + hold_us * (MS / 1000);
    m.run(hold_us * (MS / 1000));
    let updates = m.chip().mcu.tim11_updates() - before;
    // a few ms for the service task's watch (every ms) to see it
    m.run(10 * MS);
    let steps_late = m.static_u32("9telemetry10STEPS_LATE17h");
    Held { hold_us, updates, clock_before, clock_after: None, steps_late, led_code: 0 }
}

pub fn counted(m: &mut Machine) -> Counted {
    let image = m.static_u32("9telemetry10TICKS_LOST17h");
    let c = m.chip();
    let tick = crate::chip::probe::tick_exc();
    let entries = c.entries.get(&tick).copied().unwrap_or(0);
    let pending = (c.nvic.pending[tick] && !c.active.contains(&tick)) as u64;
    Counted { image, seen: c.mcu.tim11_updates().saturating_sub(entries + pending) }
}
