//! A stepper (or step/dir servo): every pulse moves the rotor one step, up
//! to a torque-speed limit beyond which the rotor stalls and the pulses are
//! lost (the driver still counts them: that is what a real one does).
//! The rotor's smooth position passes through the middle of each step, at
//! the step's instant (steps at half-step crossings, see `steps.rs`).

use polyturn_sync::steps::{Dir, StepPlan};

/// Plans a stepper holds in flight, at most: the cutter's pipeline is 2
/// ticks, and the plan being pushed makes 3.
const RING: usize = 4;

#[derive(Clone, Debug)]
pub struct Stepper {
    /// fastest step rate the motor can follow, steps/s
    pub max_rate_hz: f64,
    /// largest acceleration it can follow, steps/s²
    pub max_accel: f64,
    /// seconds from the tick's start to the first possible step (ISR latency)
    pub latency_s: f64,
    /// ticks between a plan and its emission: 0 for the tick-stepped X
    /// axis, 2 for the cutter's DMA-fed timer (`steps::pipe`)
    pub lead_ticks: usize,
    /// the plans in flight, oldest at `head` (a small ring: a `VecDeque`
    /// here was 4 % of the simulator's time)
    queue: [StepPlan; RING],
    head: usize,
    queued: usize,
    /// pulses received (the 16-bit counter the firmware reads)
    pub pulses: u64,
    /// rotor position in steps (whole steps moved)
    pub position: i64,
    pub stalled: bool,
    last_event: Option<(f64, f64)>,
    last_rate: f64,
    slow_rate: f64,
}

impl Stepper {
    pub fn new(max_rate_hz: f64, max_accel: f64, latency_s: f64, lead_ticks: usize) -> Stepper {
        Stepper {
            max_rate_hz,
            max_accel,
            latency_s,
            lead_ticks: lead_ticks.min(RING - 1),
            queue: [StepPlan::default(); RING],
            head: 0,
            queued: 0,
            pulses: 0,
            position: 0,
            stalled: false,
            last_event: None,
            last_rate: 0.0,
            slow_rate: 0.0,
        }
    }

    /// Runs one tick's plan starting at `t0`; returns the rotor's smooth
    /// position at `t0` (steps), now that the next step's time is known.
    /// A halt drops the plans in flight too.
    pub fn execute(&mut self, plan: &StepPlan, t0: f64, dt: f64, timer_hz: f64, halt: bool) -> f64 {
        // a halt drops this plan and those in flight
        if halt {
            self.queued = 0;
        } else {
            self.queue[(self.head + self.queued) % RING] = *plan;
            self.queued += 1;
        }
        let plan = if self.queued > self.lead_ticks {
            let oldest = self.queue[self.head];
            (self.head, self.queued) = ((self.head + 1) % RING, self.queued - 1);
            oldest
        } else {
            StepPlan::default()
        };
        let plan = &plan;
        let sign = if plan.dir == Dir::Forward { 1.0 } else { -1.0 };
        let n = if halt { 0 } else { plan.count as usize };
        let at = |i: usize| t0 + self.latency_s + plan.at(i as u32) as f64 / timer_hz;
        let smooth_now = self.smooth_at(t0, (n > 0).then(|| (at(0), sign)));
        // The rotor follows the pulse rate averaged over ~1 ms (its
        // mechanical time constant), not each tick's whole-step count.
        // A ramp of acceleration A puts the 1 ms and 2 ms averages A·1 ms apart.
        let pulse_rate = n as f64 / dt * sign;
        let rate = self.last_rate + (pulse_rate - self.last_rate) * (dt / 1e-3).min(1.0);
        self.slow_rate += (pulse_rate - self.slow_rate) * (dt / 2e-3).min(1.0);
        let accel = (rate - self.slow_rate) / 1e-3;
        if n > 0 && (rate.abs() > self.max_rate_hz || accel.abs() > self.max_accel) {
            self.stalled = true;
        }
        if n == 0 && rate.abs() < 1.0 {
            self.stalled = false; // at rest the rotor re-locks to the driver
        }
        self.last_rate = rate;
        // every pulse counts; a turning rotor moves a step each, and its last
        // step's middle is where the smooth position next starts from
        self.pulses += n as u64;
        if n > 0 && !self.stalled {
            self.position += sign as i64 * n as i64;
            self.last_event = Some((at(n - 1), self.position as f64 - 0.5 * sign));
        }
        smooth_now
    }

    /// Position at `t`: between the last step's middle and the next one's,
    /// when both are close; otherwise the rotor sits on its step.
    fn smooth_at(&self, t: f64, next: Option<(f64, f64)>) -> f64 {
        let here = self.position as f64;
        match (self.last_event, next) {
            (Some((tp, pp)), Some((tn, sign))) if tn - tp < 2e-3 && !self.stalled => {
                let pn = here + 0.5 * sign;
                pp + (pn - pp) * ((t - tp) / (tn - tp)).clamp(0.0, 1.0)
            }
            _ => here,
        }
    }
}

/// The fastest rate the rotor takes at once from rest (its pull-in), in
/// the model of `Stepper::execute`: the rate averaged over 1 ms and over
/// 2 ms part by the acceleration, and a jump of R from rest parts them by
/// R((1-b)^k - (1-a)^k) after k ticks (a, b each tick's share of 1 and 2
/// ms); past `max_accel` (or past `max_rate_hz`) the rotor stalls.
pub fn pull_in_hz(max_rate_hz: f64, max_accel: f64, dt: f64) -> f64 {
    let (a, b) = ((dt / 1e-3).min(1.0), (dt / 2e-3).min(1.0));
    let apart = (1..1_000).map(|k| (1.0 - b).powi(k) - (1.0 - a).powi(k)).fold(0.0, f64::max);
    match apart > 0.0 {
        true => (max_accel * 1e-3 / apart).min(max_rate_hz),
        false => max_rate_hz,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn too_fast_a_command_stalls_the_rotor_but_the_pulses_count() {
        // 4 steps per 50 µs tick is 80 kHz, eight times what it can follow.
        let mut s = Stepper::new(10_000.0, 1e12, 0.0, 0);
        let plan = StepPlan { count: 4, dir: Dir::Forward, first: 100, period: 900, ..StepPlan::default() };
        for k in 0..100 {
            s.execute(&plan, k as f64 * 50e-6, 50e-6, 100e6, false);
        }
        assert!(s.stalled);
        assert_eq!(s.pulses, 400);
        assert!(s.position < 40, "moved {} of 400", s.position);
    }
}
