//! The X axis as a scenario drives it: the core's plan to the motor either
//! through the board's own GPIO step code (`polyturn_firmware::xsteps`, one
//! pulse at a tick, at most one per two ticks, DIR a tick ahead) or, as an
//! idealised output the board has not got, each step at its planned
//! instant within the tick.

use super::stepper::Stepper;
use super::XOutput;
use polyturn_firmware::xsteps::XSteps;
use polyturn_sync::steps::StepPlan;

pub struct XAxisPlant {
    output: XOutput,
    pins: XSteps,
    motor: Stepper,
}

impl XAxisPlant {
    /// A stiff axis (it follows any rate the core plans): what limits it
    /// is the core's limits and the output.
    pub fn new(output: XOutput) -> XAxisPlant {
        XAxisPlant { output, pins: XSteps::default(), motor: Stepper::new(1e9, 1e12, 2e-6, 0) }
    }

    /// The pulse count the core reads back: what the pins emitted, or,
    /// timed, every pulse planned.
    pub fn emitted(&self) -> u16 {
        match self.output {
            XOutput::Gpio => self.pins.emitted,
            XOutput::Timed => self.motor.pulses as u16,
        }
    }

    /// One tick of the core's X plan from `t` (s); returns the axis's
    /// position in steps at `t`.
    pub fn step(&mut self, plan: &StepPlan, (t, dt): (f64, f64), timer_hz: f64, halt: bool) -> f64 {
        let plan = match self.output {
            XOutput::Timed => *plan,
            XOutput::Gpio => {
                let before = self.pins.emitted;
                let pins = self.pins.tick(plan, halt);
                // a pulse rises at the tick: the plan's first instant, 0
                let count = self.pins.emitted.wrapping_sub(before);
                StepPlan { count, dir: pins.dir, ..StepPlan::default() }
            }
        };
        self.motor.execute(&plan, t, dt, timer_hz, halt)
    }
}
