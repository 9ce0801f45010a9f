//! The step output's sweep: steady rates through the real planner and books, and
//! lathe motions through the whole controller, each on the peripheral
//! model with the interrupt's latency drawn from a range.

use super::driver::{receive, Received};
use super::latches::Latches;
use super::{Isr, Rig, TICK_LEN, TIMER_HZ};
use polyturn_stm32_model::Params;
use polyturn_sync::gear::Scale;
use polyturn_sync::steps::pipe::StepPipe;
use polyturn_sync::steps::StepTiming;
use polyturn_sync::{Config, Controller, State, TickInput, Timing};

pub const TIMING: Timing = Timing::FIRMWARE;

/// What one run shows.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub received: Received,
    /// the core's committed position at the end
    pub believed: i64,
    /// the exact target at the end
    pub exact: i64,
    /// worst error of a step's spacing against the ideal train, cycles
    pub spacing_error: Option<f64>,
    /// mean delay of the steps after their ideal instants, cycles
    pub delay: Option<f64>,
    pub target_reversals: u64,
    /// reversals of the position the core commanded (whole steps per tick)
    pub command_reversals: u64,
    pub late: u64,
    pub overruns: u64,
    pub faults: Vec<&'static str>,
    /// the shortest STEP high and low a driver must accept (cycles)
    pub pulse: u64,
    /// the DIR setup time the driver needs (cycles)
    pub dir_setup: u64,
}

impl Outcome {
    /// What the driver saw on the rig, against the core's belief and the
    /// exact target; the rest for the caller to fill.
    fn of(rig: &Rig, t: &StepTiming, believed: i64, exact: i64, faults: Vec<&'static str>) -> Outcome {
        Outcome {
            received: receive(rig.mcu.edges(), t.pulse as u64, true),
            believed,
            exact,
            spacing_error: None,
            delay: None,
            target_reversals: 0,
            command_reversals: 0,
            late: rig.late + rig.mcu.dma_requests_lost(),
            overruns: rig.overruns,
            faults,
            pulse: t.pulse as u64,
            dir_setup: t.dir_setup as u64,
        }
    }

    /// Steps the driver took, the core's belief and the exact target agree.
    pub fn exact_agreement(&self) -> bool {
        self.received.steps == self.believed && self.believed == self.exact
    }
}

fn timing(config: &Config) -> StepTiming {
    polyturn_sync::derived::Derived::new(config, TIMING).steps
}

/// A constant rate (steps/s) for `ticks` ticks: the planner and the books
/// of the real core, on the model.
pub fn steady(rate_millihz: u64, ticks: u64, isr: Isr, params: Params) -> Outcome {
    let t = timing(&Config::default());
    // the command at tick boundary j, Q16 steps (exact integer ramp)
    let q = |j: u64| ((j as u128 * rate_millihz as u128 * 65_536) / (TIMING.tick_hz as u128 * 1_000)) as i64;
    let mut rig = Rig::new(params, isr);
    let (mut books, mut ok) = (StepPipe::default(), true);
    books.start(0);
    for k in 0..ticks + 4 {
        let to = q(k.min(ticks));
        rig.tick(|counted, _| {
            ok &= books.check(counted);
            (books.plan(to, &t), false, t)
        });
    }
    let faults = if ok { vec![] } else { vec!["step-output"] };
    let mut o = Outcome::of(&rig, &t, books.position(), (q(ticks) + (1 << 15)) >> 16, faults);
    // step m (from 1) rises where the command crosses m − ½, inside the
    // window that runs tick j's plan (two ticks later, `steps::pipe`)
    let ideal = |m: i64| -> f64 {
        let c = (2 * m - 1) << 15;
        let j = (0..ticks).find(|&j| q(j + 1) >= c).unwrap_or(ticks);
        let (a, b) = (q(j), q(j + 1));
        // planned at tick j+1 (from q(j) to q(j+1)), run in tick j+3
        let start = rig.tick_start(j + 3) as f64;
        start + TICK_LEN as f64 * (c - a) as f64 / (b - a).max(1) as f64
    };
    let errors: Vec<f64> = o.received.rises.iter().enumerate().map(|(i, &r)| r as f64 - ideal(i as i64 + 1)).collect();
    let spacing = errors.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max);
    let delay = errors.iter().sum::<f64>() / errors.len().max(1) as f64;
    o.spacing_error = (errors.len() > 1).then_some(spacing);
    o.delay = (!errors.is_empty()).then_some(delay);
    o
}

/// A lathe motion (encoder counts as a function of seconds) through the
/// whole controller, engaged from rest; `estop` opens the E-stop between
/// two instants (its interrupt halts the output mid-tick), after which the
/// machinist clears and engages again.
pub fn lathe(
    config: Config,
    counts: &dyn Fn(f64) -> f64,
    seconds: f64,
    isr: Isr,
    params: Params,
    estop: Option<(f64, f64)>,
) -> Outcome {
    let t = timing(&config);
    let mut ctl = Controller::new(config, TIMING);
    let mut rig = Rig::new(params, isr);
    ctl.start(0, 0, 0);
    ctl.start_edges(Latches::clock());
    let mut latches = Latches::new(rig.tick_start(0));
    let _ = ctl.engage();
    let scale = ctl.derived().scale;
    let ticks = (seconds * TIMING.tick_hz as f64) as u64;
    let (mut faults, mut last_state) = (Vec::new(), ctl.state());
    let mut target = Turns::default();
    let mut commanded = Turns::default();
    let (mut halted, mut cleared) = (false, false);
    let mut lathe_now = 0i64;
    for k in 0..ticks {
        let now = rig.tick_start(k) as f64 / TIMER_HZ as f64;
        let open = estop.is_some_and(|(a, b)| now >= a && now < b);
        if open && !halted {
            // the E-stop interrupt, somewhere inside the tick before
            rig.estop_at(rig.tick_start(k) - TICK_LEN as u64 / 3, &t);
            halted = true;
        }
        if !open && halted && !cleared {
            ctl.clear();
            cleared = true;
        }
        if cleared && ctl.state() == State::Idle {
            let _ = ctl.engage();
        }
        rig.tick(|counted, read_at| {
            lathe_now = counts(read_at as f64 / TIMER_HZ as f64).floor() as i64;
            let lathe_edge = latches.read(counts, read_at);
            let input = TickInput {
                lathe: lathe_now as u16,
                emitted: counted,
                estop_open: open,
                lathe_edge,
                ..TickInput::default()
            };
            let out = ctl.tick(&input);
            (out.plan, out.halt, t)
        });
        ctl.service();
        if ctl.state() != last_state {
            if let State::Fault(f) = ctl.state() {
                faults.push(f.name());
            }
            last_state = ctl.state();
        }
        target.see(Scale::round(scale, lathe_now));
        commanded.see((ctl.follower().position + (1 << 15)) >> 16);
    }
    let exact = Scale::round(scale, lathe_now) + ctl.turn_offset_steps();
    Outcome {
        target_reversals: target.reversals,
        command_reversals: commanded.reversals,
        ..Outcome::of(&rig, &t, ctl.status().cutter_steps, exact, faults)
    }
}

/// Lathe counts for a speed profile: 0 → `rpm` over `ramp_s`, hold
/// `hold_s`, back to 0 over `ramp_s`, then at rest.
pub fn ramp(cpr: f64, rpm: f64, ramp_s: f64, hold_s: f64) -> impl Fn(f64) -> f64 {
    let per_s = rpm / 60.0 * cpr;
    move |t: f64| {
        let up = t.min(ramp_s);
        let mut c = 0.5 * per_s / ramp_s * up * up;
        if t > ramp_s {
            c += per_s * (t - ramp_s).min(hold_s);
        }
        if t > ramp_s + hold_s {
            let d = (t - ramp_s - hold_s).min(ramp_s);
            c += per_s * d - 0.5 * per_s / ramp_s * d * d;
        }
        c
    }
}

/// A chuck rocked by hand for `seconds`: ±`amp` counts at 3 Hz with a
/// tenth of that at 37 Hz (jitter), then left at rest.
pub fn rocking(amp: f64, seconds: f64) -> impl Fn(f64) -> f64 {
    use std::f64::consts::TAU;
    move |t: f64| {
        let t = t.min(seconds);
        amp * (TAU * 3.0 * t).sin() + 0.1 * amp * (TAU * 37.0 * t).sin()
    }
}

/// Counts the reversals of a sequence of whole-step positions.
#[derive(Default)]
struct Turns {
    last: i64,
    dir: i64,
    reversals: u64,
}

impl Turns {
    fn see(&mut self, at: i64) {
        let d = (at - self.last).signum();
        if d != 0 && self.dir != 0 && d != self.dir {
            self.reversals += 1;
        }
        if d != 0 {
            self.dir = d;
        }
        self.last = at;
    }
}
