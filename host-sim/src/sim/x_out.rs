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
    /// the screw's backlash (steps) and where the slide is (steps): it
    /// moves only when the motor pushes it from one side of the play
    backlash: f64,
    slide: f64,
}

impl XAxisPlant {
    /// A stiff axis (it follows any rate the core plans): what limits it
    /// is the core's limits and the output.
    pub fn new(output: XOutput, backlash_steps: f64) -> XAxisPlant {
        let motor = Stepper::new(1e9, 1e12, 2e-6, 0);
        XAxisPlant { output, pins: XSteps::default(), motor, backlash: backlash_steps.max(0.0), slide: 0.0 }
    }

    /// The pulse count the core reads back: what the pins emitted, or,
    /// timed, every pulse planned.
    pub fn emitted(&self) -> u16 {
        match self.output {
            XOutput::Gpio => self.pins.emitted,
            XOutput::Timed => self.motor.pulses as u16,
        }
    }

    /// One tick of the core's X plan from `t` (s); returns the slide's
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
        let motor = self.motor.execute(&plan, t, dt, timer_hz, halt);
        self.play(motor)
    }

    /// The slide behind a screw with backlash: it stays while the motor
    /// turns within the play (a reversal takes the play up first), and
    /// follows one edge of it otherwise. With none, the motor itself.
    fn play(&mut self, motor: f64) -> f64 {
        let half = self.backlash / 2.0;
        if motor > self.slide + half {
            self.slide = motor - half;
        } else if motor < self.slide - half {
            self.slide = motor + half;
        }
        self.slide
    }
}
