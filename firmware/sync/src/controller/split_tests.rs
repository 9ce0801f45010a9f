//! The tick as the firmware runs it: `control` in the tick, `plan_steps`
//! one level below (`app/tick/plan.rs`). The two in turn must give what
//! `tick` gives, tick by tick, and the plan must be made once.

use super::*;
use crate::config::Config;
use crate::state::Fault;

/// A lathe at 600 rpm of a 2 400-count encoder (0.016 count a tick, Q16)
/// and a step output that emits each plan two ticks later; engaged at tick
/// 10, the E-stop opened at tick `estop_at`.
struct Run {
    c: Controller,
    emitted: u16,
    flight: [u16; 2],
}

impl Run {
    fn new() -> Run {
        let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
        c.start(0, 0, 0);
        Run { c, emitted: 0, flight: [0; 2] }
    }

    fn input(&self, k: u32, estop_at: u32) -> TickInput {
        TickInput {
            lathe: ((k as u64 * 1_049) >> 16) as u16,
            emitted: self.emitted,
            estop_open: k >= estop_at,
            ..TickInput::default()
        }
    }

    fn emit(&mut self, k: u32, plan: &StepPlan) {
        self.emitted = self.emitted.wrapping_add(self.flight[0]);
        self.flight = [self.flight[1], plan.count];
        if k == 10 {
            assert_eq!(self.c.engage(), Ok(()));
        }
    }
}

#[test]
fn control_then_plan_steps_is_the_tick_tick_by_tick() {
    let (mut whole, mut split) = (Run::new(), Run::new());
    let (mut planned, mut synced, estop_at) = (0u32, false, 20_000);
    for k in 0..21_000 {
        let want = whole.c.tick(&whole.input(k, estop_at));
        let mut got = split.c.control(&split.input(k, estop_at));
        assert_eq!(got.plan, StepPlan::default(), "tick {k}: control leaves the plan");
        got.plan = split.c.plan_steps();
        assert_eq!(got, want, "tick {k}");
        assert_eq!(split.c.plan_steps(), StepPlan::default(), "tick {k}: the plan is made once");
        planned += want.plan.count as u32;
        synced |= split.c.state() == State::Synced;
        whole.emit(k, &want.plan);
        split.emit(k, &got.plan);
    }
    // it stepped, synchronised, and the E-stop halted it
    assert!(planned > 500 && synced, "{planned} steps planned, synchronised: {synced}");
    assert_eq!(split.c.state(), State::Fault(Fault::EStop));
}

#[test]
fn no_plan_is_left_while_idle_or_halted() {
    let mut r = Run::new();
    for k in 0..3 {
        r.c.control(&r.input(k, u32::MAX));
        assert_eq!(r.c.plan_steps(), StepPlan::default(), "idle");
    }
    r.c.control(&r.input(3, 3));
    assert_eq!(r.c.plan_steps(), StepPlan::default(), "halted");
}
