//! The simulator: the real sync core, ticked at the firmware's rate against
//! plant models of the lathe, its encoder and the cutter drive. The cutter's
//! real angle at every tick cuts the section, which is compared with the
//! geometry model's ideal section.

pub mod bldc_drive;
mod cut;
pub mod encoder;
pub mod lathe;
pub mod report;
mod rng;
mod run;
pub mod shaft;
pub mod single_point;
mod stepper;
mod x_out;

pub use cut::CutRecorder;
pub use run::run;
pub use run::start_edges;
pub use stepper::pull_in_hz;

use crate::geometry::Setup;
use lathe::LatheProfile;
use polyturn_sync::{Config, DriveKind, Fault};

/// A timed command or event, seconds from the start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    Engage(f64),
    Disengage(f64),
    /// the e-stop opens at this time (and stays open)
    EStop(f64),
    /// (tick, counts): the lathe encoder gains or drops counts
    Glitch(u64, i64),
    /// the cutter jams in the cut at this time: the stepper's rotor stops
    /// while its driver takes the pulses (the lost-step alarm's case)
    Jam(f64),
}

/// Everything a run needs. `Scenario::standard` builds the CLI's runs.
#[derive(Clone, Debug)]
pub struct Scenario {
    pub setup: Setup,
    pub core: Config,
    pub tick_hz: u32,
    pub lathe: LatheProfile,
    pub events: Vec<Event>,
    pub seed: u64,
    /// stepper: fastest and most acceleration it can follow (steps/s, /s²)
    pub motor_max_rate_hz: f64,
    pub motor_max_accel: f64,
    /// BLDC: torque limit (N·m) and cutting load (N·m)
    pub bldc_max_torque: f64,
    pub bldc_cut_torque: f64,
    /// BLDC: the drive between the firmware and the motor (what the
    /// firmware sends today: an RC ESC at 50 Hz, `BldcDrive::FIRMWARE`)
    pub bldc_drive: bldc_drive::BldcDrive,
    /// revolutions of cutting (synchronised, lathe at speed) after which the
    /// machinist withdraws the tool and stops the lathe; None: run the
    /// lathe profile as given
    pub cut_revolutions: Option<f64>,
    /// an X axis (cross-slide) driven by the core's cam, if fitted
    pub x_axis: Option<XSim>,
    /// the stepper's step-to-step position error, fraction of a step, seen
    /// by a shaft encoder (`core.cutter_encoder_cpr`, if set)
    pub step_error: f64,
    /// the lathe encoder's disc, and whether the board times its edges
    /// (`polyturn_sync::edges`: the firmware does; off, the count alone)
    pub disc: encoder::Disc,
    pub edge_timing: bool,
    /// a deliberately broken core for the "can the check fail" test:
    /// the gear's ratio numerator is off by this much
    pub sabotage_ratio_num: i32,
}

/// The X axis of a run: the cam table the core follows, and the axis.
#[derive(Clone, Debug)]
pub struct XSim {
    pub table: &'static [i32],
    pub period_counts: u32,
    pub steps_per_mm: f64,
    /// steps/s and steps/s²: the core's limits for X (the plant follows them)
    pub max_rate_hz: f64,
    pub max_accel: f64,
    /// how the steps reach the driver
    pub output: XOutput,
    /// the slide's lost motion between the motor and the tool (a screw and
    /// nut's backlash), steps; 0 for none
    pub backlash_steps: f64,
}

/// How the X steps reach the driver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum XOutput {
    /// the board's: a pulse on a GPIO pin from the control tick, at most
    /// one per two ticks, DIR a tick ahead (`polyturn_firmware::xsteps`,
    /// the very code the board runs)
    Gpio,
    /// each step at its planned instant within the tick, as a timer
    /// places the cutter's: an idealised output the board has not got
    Timed,
}

/// Start condition of the lathe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    Rest,
    Spinning,
}

/// What a run found.
#[derive(Clone, Debug)]
pub struct SimResult {
    pub final_error_steps: i64,
    pub max_error_steps: f64,
    pub max_error_deg: f64,
    /// the same, only while the tool is cutting (synced, lathe at speed)
    pub max_error_steps_cutting: f64,
    pub max_profile_deviation: f64,
    pub section: crate::geometry::Section,
    pub ideal: crate::geometry::Section,
    /// sections cut by each engagement, in order
    pub passes: Vec<crate::geometry::Section>,
    pub faults: Vec<(u64, Fault)>,
    pub ticks: u64,
    pub steps_emitted: u64,
    pub encoder_counts: i64,
    pub synced_ticks: u64,
    /// when the core first said synced (s from the run's start)
    pub first_synced_s: Option<f64>,
    /// (time s, min error, max error) in steps, decimated, for the plot
    pub error_trace: Vec<(f64, f64, f64)>,
    pub stalled: bool,
    /// with a shaft encoder: the largest distance the core measured between
    /// the steps sent and the shaft, steps (the lost-step alarm's margin)
    pub max_shaft_error_steps: f64,
    /// lathe turns cut: synchronised with the lathe at speed (0: the
    /// stock was never cut)
    pub cut_turns: f64,
}

/// The simulated board's `max-rpm` for a run at `rpm`: 30 % over it (the
/// ripple's headroom), at least 60. Times 13 then / 10, not × 1.3: exact for
/// a whole `rpm`, so `fastest_rpm_within` is its exact inverse.
pub fn max_rpm_for(rpm: f64) -> u32 {
    ((rpm * 13.0 / 10.0).ceil() as u32).max(60)
}

/// The fastest whole lathe speed whose `max_rpm_for` is at most `max_rpm`;
/// None if even the least (60) is over it.
pub fn fastest_rpm_within(max_rpm: u32) -> Option<u32> {
    (max_rpm >= 60).then(|| max_rpm * 10 / 13)
}

impl Scenario {
    /// The CLI's run: reach `rpm`, cut for `revolutions`, decelerate to rest.
    #[allow(clippy::too_many_arguments)]
    pub fn standard(
        setup: Setup,
        rpm: f64,
        revolutions: f64,
        ripple: f64,
        start: Start,
        encoder_cpr: u32,
        motor_steps: u32,
        drive: DriveKind,
        seed: u64,
    ) -> Scenario {
        let core = Config {
            encoder_counts_per_rev: encoder_cpr,
            motor_steps_per_rev: motor_steps,
            ratio: setup.ratio,
            sense: match setup.direction {
                crate::geometry::Direction::Same => polyturn_sync::Sense::Same,
                crate::geometry::Direction::Opposite => polyturn_sync::Sense::Opposite,
            },
            edges: setup.edges as u8,
            drive,
            max_lathe_rpm: max_rpm_for(rpm),
            following_error_limit_steps: (motor_steps / 50).max(16),
            ..Config::default()
        };
        let accel = 1200.0; // rpm/s: a lathe reaching 600 rpm in half a second
        let (start_rpm, engage_at) = match start {
            Start::Rest => (0.0, 0.0),
            Start::Spinning => (rpm, 0.2),
        };
        // Held until the cut is done (see `cut_revolutions`), with a cap.
        let hold = 60.0 + revolutions * 60.0 / rpm.max(1e-9);
        let legs = vec![
            lathe::Leg { rpm, accel_rpm_per_s: accel, hold_s: hold },
            lathe::Leg { rpm: 0.0, accel_rpm_per_s: accel, hold_s: 0.3 },
        ];
        Scenario {
            setup,
            core,
            tick_hz: polyturn_sync::Timing::FIRMWARE.tick_hz,
            lathe: LatheProfile { start_rpm, legs, ripple, wander: ripple / 5.0, dips: vec![] },
            events: vec![Event::Engage(engage_at)],
            seed,
            motor_max_rate_hz: 250_000.0,
            motor_max_accel: 5e6,
            bldc_max_torque: 1.0,
            bldc_cut_torque: 0.2,
            bldc_drive: bldc_drive::BldcDrive::FIRMWARE,
            cut_revolutions: Some(revolutions),
            x_axis: None,
            step_error: 0.0,
            disc: encoder::Disc::default(),
            edge_timing: true,
            sabotage_ratio_num: 0,
        }
    }

    /// The most a steady lathe's speed ripple asks of the cutter, steps/s²:
    /// the lathe's speed ω(1 + r sin θ) (`lathe.rs`) changes by up to rω²
    /// rad/s², which the gear turns into the cutter's steps. The
    /// follower makes no more than `max-accel`, so a ripple asking more
    /// leaves the cutter behind the gear.
    pub fn ripple_accel(&self, rpm: f64) -> f64 {
        let omega = rpm / 60.0 * std::f64::consts::TAU;
        let steps_per_rad = self.core.ratio.to_f64() * self.core.motor_steps_per_rev as f64 / std::f64::consts::TAU;
        self.lathe.ripple * omega * omega * steps_per_rad
    }
}
#[cfg(test)]
mod cut_tests;
