//! The tick loop: plants → sync core → plants, once per control tick.

use super::bldc_drive::Bldc;
use super::encoder::Encoder;
use super::lathe::Lathe;
use super::shaft::ShaftEncoder;
use super::stepper::Stepper;
use super::x_out::XAxisPlant;
use super::{CutRecorder, Event, Scenario, SimResult, XOutput};
use crate::geometry::Section;
use polyturn_firmware::bldcout::Out;
use polyturn_sync::edges::EdgeClock;
use polyturn_sync::gear::Scale;
use polyturn_sync::{Controller, DriveKind, Fault, State, TickInput, TickOutput, Timing};
use std::f64::consts::TAU;

/// The board's step timer clock: the simulated tick plans in its cycles.
const TIMER_HZ: u32 = Timing::FIRMWARE.step_timer_hz;

struct Plants {
    lathe: Lathe,
    encoder: Encoder,
    stepper: Stepper,
    bldc: Bldc,
    /// what TIM10 sends the BLDC drive: the core's settings fix it for
    /// the run
    bldc_out: Out,
    x: XAxisPlant,
    /// an encoder on the stepper's shaft, if the core has one set
    shaft: ShaftEncoder,
}

/// Fits the scenario's X axis to the core.
fn fit_x(ctl: &mut Controller, sc: &Scenario) -> Result<(), String> {
    let Some(x) = &sc.x_axis else { return Ok(()) };
    let cam = polyturn_sync::cam::Cam::new(x.table, x.period_counts).map_err(|e| format!("cam table: {e:?}"))?;
    let limits =
        polyturn_sync::follower::Limits::from_rates(x.max_rate_hz as u64, x.max_accel as u64, sc.tick_hz as u64);
    ctl.set_x_axis(Some(polyturn_sync::XAxis::new(cam, limits))).map_err(|r| r.describe().to_string())
}

/// Runs a scenario to the end (lathe at rest, everything settled).
pub fn run(sc: &Scenario) -> Result<SimResult, String> {
    let mut ctl = Controller::new(core_config(sc)?, Timing { tick_hz: sc.tick_hz, step_timer_hz: TIMER_HZ });
    ctl.start(0, 0, 0);
    start_edges(&mut ctl, sc);
    fit_x(&mut ctl, sc)?;
    let mut p = Plants::new(sc, &ctl);
    let bins = Section::default_bins(sc.setup.sides()).min(2048);
    let ran = event_loop(sc, &mut ctl, &mut p, bins);
    result(sc, &ctl, &mut p, bins, ran)
}

/// The board's edge times, as the firmware starts them: the first tick's
/// instant on the encoder's stamp, the count 0 in state (A,B) = (0,0).
pub fn start_edges(ctl: &mut Controller, sc: &Scenario) {
    let per_tick = super::encoder::STAMP_HZ as u32 / sc.tick_hz.max(1);
    let whole = per_tick * sc.tick_hz == super::encoder::STAMP_HZ as u32;
    if sc.edge_timing && whole {
        let first_instant = super::encoder::STAMP_ORIGIN as u16;
        ctl.start_edges(EdgeClock { first_instant, stamps_per_tick: per_tick as u16, low_low_odd: false });
    }
}

/// The scenario's settings, checked, with its sabotage applied.
fn core_config(sc: &Scenario) -> Result<polyturn_sync::Config, String> {
    sc.core.validate().map_err(|e| format!("--{} {}", e.field, e.allowed))?;
    let mut core_cfg = sc.core;
    if sc.sabotage_ratio_num != 0 {
        let num = (core_cfg.ratio.num() as i64 + sc.sabotage_ratio_num as i64).max(1) as u64;
        core_cfg.ratio =
            polyturn_sync::Ratio::new(num, core_cfg.ratio.den() as u64).map_err(|e| e.describe().to_string())?;
    }
    Ok(core_cfg)
}

impl Plants {
    fn new(sc: &Scenario, ctl: &Controller) -> Plants {
        let mut p = Plants {
            lathe: Lathe::new(sc.lathe.clone(), sc.seed),
            encoder: Encoder::with_disc(sc.core.encoder_counts_per_rev, sc.disc),
            stepper: Stepper::new(
                sc.motor_max_rate_hz,
                sc.motor_max_accel,
                0.0,
                polyturn_sync::steps::pipe::LEAD_TICKS as usize,
            ),
            bldc: Bldc::new(sc.core.motor_steps_per_rev),
            bldc_out: Out::new(ctl.config(), ctl.derived().limits.max_velocity),
            x: XAxisPlant::new(
                sc.x_axis.as_ref().map_or(XOutput::Timed, |x| x.output),
                sc.x_axis.as_ref().map_or(0.0, |x| x.backlash_steps),
            ),
            shaft: ShaftEncoder::new(sc.core.cutter_encoder_cpr, sc.core.motor_steps_per_rev, sc.step_error, sc.seed),
        };
        p.bldc.max_torque = sc.bldc_max_torque;
        p.bldc.cut_torque = sc.bldc_cut_torque;
        p.bldc.drive = sc.bldc_drive;
        // the ESC's full scale: `max-rate` counts/s as rad/s
        p.bldc.full_speed = sc.core.max_step_rate_hz as f64 / sc.core.motor_steps_per_rev as f64 * TAU;
        for e in &sc.events {
            if let Event::Glitch(t, n) = *e {
                p.encoder.glitches.push((t, n));
            }
        }
        p
    }
}

/// The gear as the scenario sets it, in floating point: motor steps and
/// encoder counts a turn, the sense's sign and the ratio.
struct Gearing {
    m: f64,
    e: f64,
    sense: f64,
    gr: f64,
}

impl Gearing {
    fn of(sc: &Scenario) -> Gearing {
        Gearing {
            m: sc.core.motor_steps_per_rev as f64,
            e: sc.core.encoder_counts_per_rev as f64,
            sense: if sc.core.sense == polyturn_sync::Sense::Same { 1.0 } else { -1.0 },
            gr: sc.core.ratio.to_f64(),
        }
    }
}

/// What the loop leaves: one recorder per engagement, the error tally and
/// the ticks run.
struct Ran {
    passes: Vec<CutRecorder>,
    out: Tally,
    tick: u64,
    /// lathe radians cut
    cut: f64,
}

/// The machinist's part: where the cut stands, in lathe angle.
#[derive(Default)]
struct Machinist {
    cut_angle: Option<f64>,
    cut_done: f64,
}

/// Ticks until the lathe has finished its profile and everything rests.
fn event_loop(sc: &Scenario, ctl: &mut Controller, p: &mut Plants, bins: usize) -> Ran {
    let dt = 1.0 / sc.tick_hz as f64;
    let Gearing { m, e, sense, gr } = Gearing::of(sc);
    // One recorder per engagement; the whole run's section is their minimum.
    let mut passes: Vec<CutRecorder> = Vec::new();
    let mut out = Tally::default();
    let (mut latched, mut tick, mut settle) = (Latched::default(), 0u64, 0u32);
    let mut last_state = ctl.state();
    let mut machinist = Machinist::default();
    let mut last_angle = p.lathe.angle;
    loop {
        let t = tick as f64 * dt;
        scheduled(sc, t, dt, ctl, &mut passes, bins, &mut latched);
        let a = p.lathe.angle;
        let count = p.encoder.count(a, tick);
        let index = p.encoder.index(a);
        p.encoder.follow(last_angle, a, t, dt);
        last_angle = a;
        let input = TickInput {
            lathe: count as u16,
            index,
            emitted: p.stepper.pulses as u16,
            cutter: p.cutter_count(sc) as u16,
            estop_open: latched.estop,
            alarm: false,
            x_emitted: p.x.emitted(),
            lathe_edge: p.encoder.edge_regs(),
        };
        let o = ctl.tick(&input);
        ctl.service();
        if let Some(m) = ctl.lost_milli_steps() {
            out.max_shaft = out.max_shaft.max(m.unsigned_abs() as f64 / 1e3);
        }
        if latched.jam {
            p.stepper.stalled = true; // the rotor held; the driver counts on
        }
        let steps_now = match sc.core.drive {
            DriveKind::Stepper | DriveKind::None => p.stepper.execute(&o.plan, t, dt, TIMER_HZ as f64, o.halt),
            DriveKind::Bldc => p.bldc.angle / TAU * m,
        };
        p.shaft.update(steps_now);
        let theta = steps_now / m * TAU;
        let dx = match &sc.x_axis {
            Some(x) => p.x.step(&o.x_plan, (t, dt), TIMER_HZ as f64, o.halt) / x.steps_per_mm,
            None => 0.0,
        };
        let state = ctl.state();
        if state != last_state {
            if let State::Fault(f) = state {
                out.faults.push((tick, f));
                if sc.cut_revolutions.is_some() {
                    p.lathe.end_hold(); // the machinist stops the lathe
                }
            }
            last_state = state;
        }
        // The machinist feeds the tool in once synchronised at speed and
        // withdraws it before the lathe slows (ripple and dips still count).
        let cutting = state == State::Synced && p.lathe.holding();
        if state == State::Synced {
            let ideal = sense * gr * m * (a / TAU * e - ctl.gear_origin() as f64) / e + ctl.turn_offset_steps() as f64;
            out.error(t, ideal - steps_now, cutting);
        }
        machinist.cut(sc, cutting, &mut p.lathe, passes.last_mut(), (a, theta, dx));
        if sc.core.drive == DriveKind::Bldc {
            p.drive_bldc(sc, &o, (t, dt), cutting);
        }
        p.lathe.advance(dt);
        tick += 1;
        // Done once the lathe has finished its profile and the cutter rests.
        let resting = p.lathe.finished() && ctl.follower().velocity == 0 && p.bldc.speed.abs() < 0.05;
        settle = if resting { settle + 1 } else { 0 };
        if settle > sc.tick_hz / 5 || tick > 3_600 * sc.tick_hz as u64 {
            break;
        }
    }
    Ran { passes, out, tick, cut: machinist.cut_done }
}

/// The events that hold once they have come: the E-stop open, the cutter
/// jammed.
#[derive(Default)]
struct Latched {
    estop: bool,
    jam: bool,
}

impl Plants {
    /// The BLDC for a tick: the drive takes the pulse the firmware makes of
    /// the core's command (`app/tick.rs`), and the motor turns the way it is
    /// wired (the gear's), under the cut's load while an edge is in it.
    fn drive_bldc(&mut self, sc: &Scenario, o: &TickOutput, (t, dt): (f64, f64), cutting: bool) {
        let Gearing { m, sense, .. } = Gearing::of(sc);
        let cmd = o.speed_q16 as f64 / 65536.0 * sc.tick_hz as f64 * TAU / m;
        let ccr = self.bldc_out.command(o.enable && !o.halt, o.speed_q16, sense > 0.0);
        self.bldc.take(t, ccr, &self.bldc_out, cmd, sense);
        let load = cutting && tip_in_stock(&sc.setup, self.bldc.angle);
        self.bldc.advance(load, o.enable, dt);
    }

    /// What TIM4 reads: the shaft encoder on a stepper that has one, else
    /// the BLDC's encoder.
    fn cutter_count(&self, sc: &Scenario) -> i64 {
        match sc.core.drive {
            DriveKind::Stepper if self.shaft.cpr != 0 => self.shaft.count,
            DriveKind::Bldc => self.bldc.count(),
            // nothing on TIM4 (the BLDC plant never turns without its drive)
            _ => 0,
        }
    }
}

/// The scenario's events due in the tick starting at `t`: an engagement
/// that the core takes starts a new pass.
fn scheduled(
    sc: &Scenario,
    t: f64,
    dt: f64,
    ctl: &mut Controller,
    passes: &mut Vec<CutRecorder>,
    bins: usize,
    latched: &mut Latched,
) {
    for ev in &sc.events {
        match *ev {
            Event::Engage(at) if at <= t && at > t - dt && ctl.engage().is_ok() => {
                passes.push(CutRecorder::new(&sc.setup, bins));
            }
            Event::Disengage(at) if at <= t && at > t - dt => ctl.disengage(),
            Event::EStop(at) if at <= t => latched.estop = true,
            Event::Jam(at) if at <= t => latched.jam = true,
            _ => {}
        }
    }
}

impl Machinist {
    /// Records the cut while `cutting` (the lathe at `a`, the cutter at
    /// `theta`, X at `dx`), and stops the lathe after the scenario's
    /// revolutions of cutting.
    fn cut(
        &mut self,
        sc: &Scenario,
        cutting: bool,
        lathe: &mut Lathe,
        pass: Option<&mut CutRecorder>,
        (a, theta, dx): (f64, f64, f64),
    ) {
        if cutting {
            if let Some(last) = self.cut_angle.replace(a) {
                self.cut_done += (a - last).abs();
            }
            if sc.cut_revolutions.is_some_and(|n| self.cut_done >= n * TAU) {
                lathe.end_hold();
            }
            if let Some(pass) = pass {
                pass.record(a, theta, dx);
            }
        } else {
            self.cut_angle = None;
            if let Some(pass) = pass {
                pass.pause();
            }
        }
    }
}

/// The figures of a finished run: the final error against the exact gear,
/// the section cut (the minimum of the passes) against the ideal.
fn result(sc: &Scenario, ctl: &Controller, p: &mut Plants, bins: usize, ran: Ran) -> Result<SimResult, String> {
    let Ran { passes, out, tick, cut } = ran;
    let Gearing { m, sense, gr, .. } = Gearing::of(sc);
    let a = p.lathe.angle;
    let count = p.encoder.count(a, tick);
    let scale = Scale::new(
        sc.core.ratio.num(),
        sc.core.ratio.den(),
        sc.core.motor_steps_per_rev,
        sc.core.encoder_counts_per_rev,
    )
    .ok_or("zero scale")?;
    let rel = count - ctl.gear_origin();
    let exact = scale.round(if sense > 0.0 { rel } else { -rel }) + ctl.turn_offset_steps();
    let cutter = match sc.core.drive {
        DriveKind::Stepper | DriveKind::None => p.stepper.position,
        DriveKind::Bldc => p.bldc.count(),
    };
    let passes: Vec<Section> = passes.iter().map(CutRecorder::section).collect();
    let mut section = CutRecorder::new(&sc.setup, bins).section();
    for p in &passes {
        for (r, q) in section.envelope.radius.iter_mut().zip(&p.envelope.radius) {
            *r = r.min(*q);
        }
    }
    let ideal = Section::ideal_tiled(&sc.setup, bins);
    let max_profile_deviation = section
        .envelope
        .radius
        .iter()
        .enumerate()
        .map(|(i, r)| (r - ideal.envelope.radius[i]).abs())
        .fold(0.0, f64::max);
    Ok(SimResult {
        final_error_steps: exact - cutter,
        max_error_steps: out.max_abs,
        max_error_deg: out.max_abs * 360.0 / (m * gr),
        max_error_steps_cutting: out.max_cutting,
        max_profile_deviation,
        section,
        ideal,
        passes,
        faults: out.faults,
        ticks: tick,
        steps_emitted: p.stepper.pulses,
        encoder_counts: count,
        synced_ticks: out.synced,
        first_synced_s: out.first_synced_s,
        error_trace: out.trace,
        stalled: p.stepper.stalled,
        max_shaft_error_steps: out.max_shaft,
        cut_turns: cut / TAU,
    })
}

/// Whether any edge is inside the stock (for the BLDC's cutting load).
fn tip_in_stock(setup: &crate::geometry::Setup, theta: f64) -> bool {
    let c = setup.in_stock_cos();
    (0..setup.edges).any(|j| (theta + TAU * j as f64 / setup.edges as f64).cos() > c)
}

#[derive(Default)]
struct Tally {
    max_shaft: f64,
    max_abs: f64,
    max_cutting: f64,
    synced: u64,
    first_synced_s: Option<f64>,
    faults: Vec<(u64, Fault)>,
    trace: Vec<(f64, f64, f64)>,
    bucket: Option<(f64, f64, f64)>,
}

impl Tally {
    fn error(&mut self, t: f64, err: f64, cutting: bool) {
        self.synced += 1;
        self.first_synced_s.get_or_insert(t);
        self.max_abs = self.max_abs.max(err.abs());
        if cutting {
            self.max_cutting = self.max_cutting.max(err.abs());
        }
        let b = self.bucket.get_or_insert((t, err, err));
        b.1 = b.1.min(err);
        b.2 = b.2.max(err);
        if t - b.0 >= 0.002 {
            self.trace.push(*b);
            self.bucket = None;
        }
    }
}
