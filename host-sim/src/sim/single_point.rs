//! Noncircular turning in the simulator (the noncircular turning note,
//! "Noncircular Turning of Workpieces With Sharp Corners"): a single-point tool on
//! the X cam, the real core with `drive=none`, the section recorded as the
//! lowest tool radius at each workpiece angle over every revolution cut.

use super::encoder::Encoder;
use super::lathe::{Lathe, LatheProfile, Leg};
use super::x_out::XAxisPlant;
use super::XOutput;
use crate::noncircular::path::ToolPath;
use crate::noncircular::table::CamFile;
use polyturn_sync::{Config, Controller, DriveKind, Fault, State, TickInput, Timing};
use std::f64::consts::TAU;

const TICK_HZ: u32 = Timing::FIRMWARE.tick_hz;
const TIMER_HZ: u32 = Timing::FIRMWARE.step_timer_hz;
const BINS: usize = 4096;

/// A single-point run: the lathe at `rpm` (with `ripple`), the core on
/// `table`, cutting `revolutions` once synchronised.
#[derive(Clone, Debug)]
pub struct SinglePoint {
    pub table: CamFile,
    pub apothem_mm: f64,
    pub rpm: f64,
    pub ripple: f64,
    pub revolutions: f64,
    pub seed: u64,
    /// how X's steps reach the driver
    pub output: XOutput,
    /// the cross-slide's backlash, steps (0: none)
    pub backlash_steps: f64,
}

#[derive(Clone, Debug)]
pub struct SinglePointResult {
    /// cut − planned section per workpiece-angle bin, mm (min over passes)
    pub deviation: Vec<f64>,
    /// the largest |deviation|, mm (infinite if an angle was never cut)
    pub max_deviation: f64,
    pub faults: Vec<Fault>,
    pub synced_ticks: u64,
}

fn controller(sc: &SinglePoint) -> Result<Controller, String> {
    let t = &sc.table;
    let config = Config {
        encoder_counts_per_rev: t.counts_per_rev,
        drive: DriveKind::None,
        max_lathe_rpm: super::max_rpm_for(sc.rpm),
        ..Config::default()
    };
    config.validate().map_err(|e| format!("--{} {}", e.field, e.allowed))?;
    let mut ctl = Controller::new(config, Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    // the firmware's own path: the same checks as a table from flash
    ctl.fit_cam(&t.header(), Vec::leak(t.points.clone()))?;
    Ok(ctl)
}

/// Runs the cut and compares it with `planned` (the path the table samples).
pub fn run(sc: &SinglePoint, planned: &dyn ToolPath) -> Result<SinglePointResult, String> {
    let mut ctl = controller(sc)?;
    let legs = vec![
        Leg { rpm: sc.rpm, accel_rpm_per_s: 100.0, hold_s: 3600.0 },
        Leg { rpm: 0.0, accel_rpm_per_s: 100.0, hold_s: 0.3 },
    ];
    let profile = LatheProfile { start_rpm: sc.rpm, legs, ripple: sc.ripple, wander: sc.ripple / 5.0, dips: vec![] };
    let (mut lathe, mut encoder) = (Lathe::new(profile, sc.seed), Encoder::new(sc.table.counts_per_rev));
    let mut x = XAxisPlant::new(sc.output, sc.backlash_steps);
    let (dt, spm) = (1.0 / TICK_HZ as f64, sc.table.steps_per_mm);
    let cpr = sc.table.counts_per_rev as f64;
    let (mut deviation, mut faults, mut synced) = (vec![f64::INFINITY; BINS], Vec::new(), 0u64);
    let (mut cut_from, mut tick, mut settle) = (None::<f64>, 0u64, 0u32);
    loop {
        let t = tick as f64 * dt;
        // engaged a second after the lathe is at speed, as at the machine
        if tick == TICK_HZ as u64 {
            ctl.engage().map_err(|r| r.describe().to_string())?;
        }
        let a = lathe.angle;
        let input = TickInput {
            lathe: encoder.count(a, tick) as u16,
            index: encoder.index(a),
            x_emitted: x.emitted(),
            lathe_edge: None,
            ..TickInput::default()
        };
        let o = ctl.tick(&input);
        ctl.service();
        let x_steps = x.step(&o.x_plan, (t, dt), TIMER_HZ as f64, o.halt);
        if let State::Fault(f) = ctl.state() {
            if faults.last() != Some(&f) {
                faults.push(f);
                lathe.end_hold();
            }
        }
        if ctl.state() == State::Synced && lathe.holding() {
            synced += 1;
            // the workpiece angle under the tool, from the cam's origin
            let phi = a - ctl.gear_origin() as f64 / cpr * TAU;
            let start = *cut_from.get_or_insert(a);
            let radius = sc.apothem_mm + x_steps / spm;
            let bin = ((phi / TAU).rem_euclid(1.0) * BINS as f64) as usize % BINS;
            deviation[bin] = deviation[bin].min(radius - planned.section(phi));
            if a - start >= sc.revolutions * TAU {
                ctl.disengage();
                lathe.end_hold();
            }
        }
        lathe.advance(dt);
        tick += 1;
        settle = if lathe.finished() && ctl.state() == State::Idle { settle + 1 } else { 0 };
        if settle > TICK_HZ / 5 || tick > 600 * TICK_HZ as u64 {
            break;
        }
    }
    let max_deviation = deviation.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    Ok(SinglePointResult { deviation, max_deviation, faults, synced_ticks: synced })
}
