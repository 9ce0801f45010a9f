//! One lathe trace for every controller: the simulator's lathe and
//! encoder stepped every µs; polyturn's real core ticked every tick with
//! the count and the edge registers the board latches (as `sim::run`),
//! Clough42 every 5 µs, nanoELS every loop pass, Didge at each edge's
//! time (interpolated within the µs). Each leaves its step times.

use super::{clough42::Clough42, didge::Didge, nanoels::NanoEls, Case};
use polyturn_host::sim::encoder::Encoder;
use polyturn_host::sim::lathe::Lathe;
use polyturn_sync::steps::{pipe::LEAD_TICKS, Dir, StepPlan};
use polyturn_sync::{Controller, State, TickInput, Timing};
use std::collections::VecDeque;
use std::f64::consts::TAU;

const DT: f64 = 1e-6;
/// µs a polyturn tick (50 at 20 kHz) and its step timer's clock.
const TICK_US: u64 = 1_000_000 / Timing::FIRMWARE.tick_hz as u64;
const _: () = assert!(1_000_000 % Timing::FIRMWARE.tick_hz == 0, "a tick is a whole number of µs");
const TIMER_HZ: f64 = Timing::FIRMWARE.step_timer_hz as f64;

/// A measuring instant (every polyturn tick).
pub struct Instant {
    pub t: f64,
    /// the lathe's true position, counts
    pub u: f64,
    /// the lathe holds its speed: the tool is in the cut
    pub cutting: bool,
    /// polyturn's core says it is synchronised
    pub synced: bool,
}

/// Step times (s, ±1) for each of `super::NAMES`; and the instants.
pub struct Trace {
    pub instants: Vec<Instant>,
    pub steps: [Vec<(f64, i32)>; 6],
    /// polyturn's gear origin (counts) and whole turns dropped (steps)
    pub origin: (i64, i64),
    pub faults: Vec<polyturn_sync::Fault>,
}

struct Polyturn {
    ctl: Controller,
    flight: VecDeque<StepPlan>,
    emitted: u64,
}

impl Polyturn {
    fn new(case: &Case) -> Result<Polyturn, String> {
        let timing = Timing::FIRMWARE;
        let mut ctl = Controller::new(case.sc.core, timing);
        ctl.start(0, 0, 0);
        polyturn_host::sim::start_edges(&mut ctl, &case.sc);
        ctl.engage().map_err(|r| r.describe().to_string())?;
        Ok(Polyturn { ctl, flight: VecDeque::new(), emitted: 0 })
    }

    /// A tick at `t`: its plan runs `LEAD_TICKS` later (`steps::pipe`).
    fn tick(&mut self, t: f64, count: i64, enc: &Encoder, out: &mut Vec<(f64, i32)>) {
        let input = TickInput {
            lathe: count as u16,
            emitted: self.emitted as u16,
            lathe_edge: enc.edge_regs(),
            ..TickInput::default()
        };
        let o = self.ctl.tick(&input);
        self.ctl.service();
        self.flight.push_back(o.plan);
        if self.flight.len() as i64 > LEAD_TICKS {
            let p = self.flight.pop_front().unwrap_or_default();
            let sign = if p.dir == Dir::Forward { 1 } else { -1 };
            out.extend((0..p.count as u32).map(|i| (t + p.at(i) as f64 / TIMER_HZ, sign)));
            self.emitted += p.count as u64;
        }
    }
}

/// Runs `case`'s lathe from rest to its speed, `case.revolutions` turns
/// there, and back to rest, with every controller engaged from the start.
pub fn run(case: &Case) -> Result<Trace, String> {
    let sc = &case.sc;
    let cpr = sc.core.encoder_counts_per_rev;
    let (num, den) =
        (sc.core.ratio.num() as u64 * sc.core.motor_steps_per_rev as u64, sc.core.ratio.den() as u64 * cpr as u64);
    let sense = if sc.core.sense == polyturn_sync::Sense::Same { 1 } else { -1 };
    let accel = sc.core.max_accel_steps_per_s2 as i64;
    let mut poly = Polyturn::new(case)?;
    let mut clough = [Clough42::new(num, den, sense, false), Clough42::new(num, den, sense, true)];
    let chain =
        (sc.core.motor_steps_per_rev, sc.core.ratio.num() as i64 * sense as i64, sc.core.ratio.den() as u64, cpr);
    let mut nano = NanoEls::new(chain, sc.core.motor_steps_per_rev as i64, accel);
    let mut didge = [Didge::new(num, den, sense, false), Didge::new(num, den, sense, true)];
    let mut steps: [Vec<(f64, i32)>; 6] = Default::default();
    let mut lathe = Lathe::new(case.profile(), sc.seed);
    let mut enc = Encoder::with_disc(cpr, sc.disc);
    let (mut instants, mut faults) = (Vec::new(), Vec::new());
    let (mut last_a, mut last_count, mut hold_from) = (0.0, 0i64, None::<f64>);
    let u_of = |a: f64| a / TAU * cpr as f64;
    for k in 0u64.. {
        let t = k as f64 * DT;
        let a = lathe.angle;
        enc.follow(last_a, a, t, DT);
        let count = enc.count(a, 0);
        if count > last_count {
            // (one count a µs at most: 36 000 counts/s at 900 rpm; up only)
            let b = enc.boundary_up(count);
            let (u0, u1) = (enc.position(last_a), enc.position(a));
            let at = t - DT + DT * (b - u0) / (u1 - u0);
            let a_rise = count.rem_euclid(4) == 1 && count > last_count;
            for (d, out) in didge.iter_mut().zip(steps[4..].iter_mut()) {
                out.extend(d.edge(at, count, a_rise));
            }
        }
        last_count = count;
        if k % TICK_US == 0 {
            poly.tick(t, count, &enc, &mut steps[0]);
            let synced = poly.ctl.state() == State::Synced;
            if let State::Fault(f) = poly.ctl.state() {
                faults.push(f);
            }
            instants.push(Instant { t, u: u_of(a), cutting: lathe.holding(), synced });
        }
        if k % 5 == 0 {
            for (c, out) in clough.iter_mut().zip(steps[1..3].iter_mut()) {
                out.extend(c.tick(count).map(|d| (t, d)));
            }
        }
        if k % (super::nanoels::LOOP_S / DT).round() as u64 == 0 {
            steps[3].extend(nano.pass(t, count));
        }
        // the machinist stops the lathe after the case's turns at speed
        if lathe.holding() {
            let from = *hold_from.get_or_insert(a);
            if a - from >= case.revolutions * TAU {
                lathe.end_hold();
            }
        }
        last_a = a;
        lathe.advance(DT);
        if lathe.finished() {
            break; // (its last leg holds it at rest: everything has settled)
        }
    }
    let origin = (poly.ctl.gear_origin(), poly.ctl.turn_offset_steps());
    Ok(Trace { instants, steps, origin, faults })
}
