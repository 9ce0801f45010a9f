//! A step plan not written by the next tick, on the real image
//! (`app::tick::plan`). Mid-cut, either its handler is held off for three
//! ticks (`How::HeldOff`, as a section masking its level and not the
//! tick's would; the image has none), or it stalls inside its write
//! (`How::Stalled`, as a flash operation stalls the CPU, at its first read
//! of DMA2's NDTR) while the ticks run on.
//!
//! The DMA asks for a window's first segment late in the tick before it
//! (`stepgen::entries::late_boundary`), so a plan written after the next
//! tick has begun is in time, and costs nothing: a held-off plan is
//! written by the tick that finds it waiting (`plan::settle`), a stalled
//! one by its handler once the stall ends. The image must then step as
//! the host's plan, tick by tick, with no fault and no late plan, and
//! count the plans written past the next tick (`plan::PAST_NEXT`). A stall
//! that keeps the write from its first segment until the DMA has asked for
//! it is late for real: the write's own check, or the tick after next that
//! finds the plan still being written, stops TIM1, and the cutter stops
//! with `fault=step-output` (LED code 7): the window the plan was for went
//! out without its steps.

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

    /// Whether the plan misses its window: a stall in its write that, with
    /// the tick it holds off run after it, ends past the tick after next,
    /// where the DMA has asked for the window's first segment (65 µs from
    /// about half a tick after its own tick ends at 1.85 ticks, and the next
    /// tick's half tick after that; 50 µs ends near 1.5 ticks, in time). A
    /// held-off plan never (the tick writes it). (A stall past two ticks
    /// would lose a tick too: the CPU answers no interrupt while stalled.)
    pub fn misses(self) -> bool {
        matches!(self, How::Stalled { us } if us >= 65)
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Late {
    pub how: How,
    /// cycles from the cause to the first write stopping TIM1
    pub stopped_after: Option<u64>,
    /// `app::tick::plan::LATES` after the job
    pub lates: Option<u32>,
    /// `app::tick::plan::PAST_NEXT` after the job: plans written after the
    /// next tick began
    pub past_next: Option<u32>,
    /// `app::tick::STEPS_LATE` after the job
    pub steps_late: Option<u32>,
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
        let past_next = m.static_u32("4plan9PAST_NEXT17h");
        let steps_late = m.static_u32("9telemetry10STEPS_LATE17h");
        Late { clock_after, lates, past_next, steps_late, led_code: super::estop::flashes(m), ..self }
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
    Late {
        how,
        stopped_after,
        lates: None,
        past_next: None,
        steps_late: None,
        clock_before,
        clock_after: None,
        led_code: 0,
    }
}
