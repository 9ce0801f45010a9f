//! A step plan not made by the next tick, on the real image
//! (`app::tick::plan`). Mid-cut, either its handler is held off for more
//! than two ticks (`How::HeldOff`, as a section masking its level and not
//! the tick's would; the image has none), so a tick finds the plan owed and
//! never started (`plan::settle`); or it stalls inside the plan
//! (`How::Stalled`, as a flash operation stalls the CPU, at its first read
//! of DMA2's NDTR), so the next tick pre-empts it while it holds the core
//! (`plan::making`) and does not run. Either way the image must stop TIM1
//! in the tick that finds it, count one late plan, and stop the cutter with
//! `fault=step-output` (LED code 7): the window the plan was for went out
//! without its steps. The stalled one also loses the tick it pre-empted:
//! the image counts it lost and measures its edge clock again (`job::lost`).

use super::MS;
use crate::machine::Machine;

/// How the plan is made late.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum How {
    HeldOff { us: u64 },
    Stalled { us: u64 },
}

impl How {
    pub fn cycles(self) -> u64 {
        match self {
            How::HeldOff { us } | How::Stalled { us } => us * (MS / 1000),
        }
    }

    /// Ticks whose core did not run: the stalled plan's pre-empting tick.
    pub fn ticks_skipped(self) -> u64 {
        matches!(self, How::Stalled { .. }) as u64
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Late {
    pub how: How,
    /// cycles from the cause to the first write stopping TIM1
    pub stopped_after: Option<u64>,
    /// `app::tick::plan::LATES` after the job
    pub lates: Option<u32>,
    /// the edge clock's first instant before, and after the job
    pub clock_before: Option<u16>,
    pub clock_after: Option<u16>,
    /// the LED's fault code after the job (`led::fault_code`; 0: none)
    pub led_code: u32,
}

impl Late {
    pub fn judged(self, m: &mut Machine) -> Late {
        let clock_after = m.edge_clock().map(|c| c.0.first_instant);
        let lates = lates(m);
        Late { clock_after, lates, led_code: super::estop::flashes(m), ..self }
    }
}

/// The image's late plans since boot (None: no such symbol in the image).
pub fn lates(m: &Machine) -> Option<u32> {
    m.static_u32("4plan5LATES17h")
}

pub fn cause(m: &mut Machine, at_s: f64, how: How) -> Late {
    m.run((at_s * 1000.0) as u64 * MS);
    let clock_before = m.edge_clock().map(|c| c.0.first_instant);
    let c = m.chip();
    (c.probe.edge_at, c.probe.step_timer_stopped) = (Some(c.now), None);
    match how {
        How::HeldOff { .. } => c.plan_held_until = c.now + how.cycles(),
        How::Stalled { .. } => c.probe.stall_in_plan = Some(how.cycles()),
    }
    // the cause, then two ticks for the stop (a stall waits for its plan)
    m.run(how.cycles() + 3 * MS / 25);
    let c = m.chip();
    let stopped_after = c.probe.step_timer_stopped.zip(c.probe.edge_at).map(|(s, e)| s - e);
    c.probe.edge_at = None;
    // a few ms for the service task's watch (every ms) to see a lost tick
    m.run(10 * MS);
    Late { how, stopped_after, lates: None, clock_before, clock_after: None, led_code: 0 }
}
