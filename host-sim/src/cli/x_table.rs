//! The X axis as the board runs it, shared by `cam` and `compensate`: the
//! flags that make a cam table for the board (its steps per mm, the lathe
//! encoder, the file) and the board's limits on the axis, so that a table
//! either command writes is one the board takes (`device upload-cam`).

use super::errors::{CliError, CliResult};
use super::values::{out_file, setting, within};
use crate::noncircular::table::{CamFile, STEPS_PER_MM};
use polyturn_sync::cam::{Cam, CamError};
use polyturn_sync::cam_upload::motion::MotionError;
use polyturn_sync::config::table::CPR;
use std::path::PathBuf;

/// The firmware emits at most one X step per two control ticks.
pub const X_MAX_RATE_HZ: f64 = polyturn_sync::cam_upload::X_MAX_RATE_HZ as f64;

// Numbers take a leading '-' as a value, so that it is refused naming its
// flag rather than read as flags.
#[derive(clap::Args, Debug)]
pub struct TableArgs {
    /// X axis steps per mm of tool radius: a 1 mm screw, 200-step motor at 256 microsteps is 51200; under 1 a step is more than ten times the 0.1 mm a table may be off [default: 800]
    #[arg(long = "steps-per-mm", value_name = "STEPS/MM", allow_hyphen_values = true, value_parser = within(STEPS_PER_MM.0, STEPS_PER_MM.1, "steps/mm"))]
    pub given_steps_per_mm: Option<f64>,
    /// Lathe encoder counts per turn, after x4 quadrature [default: 2400]
    #[arg(long = "encoder-cpr", alias = "encoder-counts", value_name = "COUNTS", allow_hyphen_values = true, value_parser = setting(CPR))]
    pub given_encoder_counts: Option<u32>,
    /// Write the cam table (JSON, for `polyturn device upload-cam`) to this file (- for stdout)
    #[arg(long, value_name = "FILE", value_parser = out_file)]
    pub table: Option<PathBuf>,
}

impl TableArgs {
    pub fn steps_per_mm(&self) -> f64 {
        self.given_steps_per_mm.unwrap_or(800.0)
    }

    pub fn encoder_counts(&self) -> u32 {
        self.given_encoder_counts.unwrap_or(2400)
    }

    /// For a command whose plan stands without the board (`compensate`
    /// plans for any X axis): the board's flags only with `--table`, so
    /// that none is taken and ignored.
    pub fn only_with_a_table(&self) -> CliResult<()> {
        let given =
            [("steps-per-mm", self.given_steps_per_mm.is_some()), ("encoder-cpr", self.given_encoder_counts.is_some())];
        match given.iter().find(|(_, g)| *g) {
            Some((flag, _)) if self.table.is_none() => Err(CliError::flag(
                flag,
                "describes the board's table: give --table FILE with it (without a table the plan is for any X axis, and the board's limits are not checked)".to_string(),
            )),
            _ => Ok(()),
        }
    }
}

/// The X axis's limits as the firmware takes them, in whole steps/s and
/// steps/s² (`cam_upload::check_axis`): at most X_MAX_RATE_HZ, at least 1.
pub fn rates(max_speed: f64, max_accel: f64, spm: f64) -> CliResult<(u32, u32)> {
    if max_speed * spm > X_MAX_RATE_HZ {
        let top = X_MAX_RATE_HZ / spm;
        return Err(CliError::flag(
            "x-max-speed",
            format!("must be <= {top:.1} mm/s: the firmware emits at most {X_MAX_RATE_HZ} X steps/s ({spm} steps/mm)"),
        ));
    }
    if max_speed * spm < 1.0 {
        return Err(CliError::flag(
            "x-max-speed",
            format!("must be >= {} mm/s: at least one X step per second ({spm} steps/mm)", 1.0 / spm),
        ));
    }
    if max_accel * spm < 1.0 {
        return Err(CliError::flag(
            "x-max-accel",
            format!("must be >= {} mm/s^2: at least one X step per second squared ({spm} steps/mm)", 1.0 / spm),
        ));
    }
    Ok(((max_speed * spm) as u32, (max_accel * spm) as u32))
}

/// A table with no room for the board's 2 points a table at least, a
/// lathe count each: the X motion repeats within a count (6 flats a turn
/// on a 6-count encoder), which only a finer encoder mends.
fn too_few_counts(table: &CamFile) -> CliError {
    let every = match table.period_counts {
        1 => "every count".to_string(),
        p => format!("every {p} counts"),
    };
    CliError::flag(
        "encoder-cpr",
        format!(
            "must give the X motion at least 2 lathe counts a repeat, one for each of the at least 2 points of the board's cam table: at {} counts a turn it repeats {every}; give an encoder of more counts a turn, in {}..={} (got {})",
            table.counts_per_rev, CPR.lo, CPR.hi, table.counts_per_rev
        ),
    )
}

/// The board's own checks of a table (`controller::check_table`): its
/// points and period (`Cam::check`), and what they ask of the axis it
/// declares (`cam_upload::motion`), refused naming the flag that fixes it.
pub fn board_takes(table: &CamFile) -> CliResult<()> {
    Cam::check(&table.points, table.period_counts).map_err(|e| match e {
        CamError::Step => CliError::flag("steps-per-mm", format!("is too fine for this path: {}", e.describe())),
        CamError::Points | CamError::Period => too_few_counts(table),
    })?;
    polyturn_sync::cam_upload::motion::check(&table.header(), &table.points).map_err(|e| match e {
        MotionError::Rate { .. } => CliError::flag("x-max-speed", e.to_string()),
        MotionError::Accel { .. } => CliError::flag("x-max-accel", e.to_string()),
    })
}
