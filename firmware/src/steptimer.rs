//! Register values for the step timer (TIM1, PWM mode 2, one-pulse mode,
//! repetition counter = steps − 1), computed from a `StepPlan` on the host-
//! testable side so the MCU code only writes them.
//!
//! In PWM mode 2 the output is high from CCR1 to ARR: each cycle ends with a
//! pulse of `pulse` ticks, whose rising edge is the step. The first cycle is
//! stretched (its ARR/CCR1 written directly, the steady ones preloaded for
//! the first update event) so the first step falls exactly at `first`.

use polyturn_sync::steps::StepPlan;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimerProgram {
    /// first cycle: ARR and CCR1 (the step's rising edge at CCR1)
    pub first_arr: u16,
    pub first_ccr: u16,
    /// later cycles
    pub arr: u16,
    pub ccr: u16,
    /// repetition counter: cycles − 1
    pub rcr: u8,
}

/// None when there is nothing to emit. `pulse` is the high time in timer
/// ticks; periods and offsets beyond 16 bits are clamped (the planner keeps
/// them within a tick, 3840 ticks at 96 MHz / 25 kHz).
pub fn program(plan: &StepPlan, pulse: u16) -> Option<TimerProgram> {
    if plan.count == 0 {
        return None;
    }
    let clamp16 = |v: u32| v.min(u16::MAX as u32) as u16;
    let period = plan.period.max(2 * pulse as u32);
    let first = plan.first.max(1);
    Some(TimerProgram {
        first_arr: clamp16(first + pulse as u32 - 1),
        first_ccr: clamp16(first),
        arr: clamp16(period - 1),
        ccr: clamp16(period - pulse as u32),
        rcr: (plan.count.min(256) - 1) as u8,
    })
}

/// Times (timer ticks from the start) of the rising edges the program makes.
pub fn edges(p: &TimerProgram) -> impl Iterator<Item = u32> + '_ {
    let first = p.first_ccr as u32;
    let after = p.first_arr as u32 + 1;
    (0..=p.rcr as u32).map(move |i| if i == 0 { first } else { after + (i - 1) * (p.arr as u32 + 1) + p.ccr as u32 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use polyturn_sync::steps::Dir;

    #[test]
    fn the_timer_puts_every_step_where_the_plan_says() {
        let plan = StepPlan { count: 5, dir: Dir::Forward, first: 700, period: 600 };
        let p = program(&plan, 96).unwrap();
        let got: Vec<u32> = edges(&p).collect();
        let want: Vec<u32> = (0..5).map(|i| 700 + i * 600).collect();
        assert_eq!(got, want);
    }

    #[test]
    fn a_single_late_step_and_nothing_at_all() {
        let plan = StepPlan { count: 1, dir: Dir::Reverse, first: 3000, period: 0 };
        assert_eq!(edges(&program(&plan, 96).unwrap()).collect::<Vec<_>>(), vec![3000]);
        assert_eq!(program(&StepPlan::default(), 96), None);
    }
}
