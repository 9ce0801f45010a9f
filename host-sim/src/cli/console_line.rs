//! What may go to the board as one console line, and a `polyturn cam`
//! table checked line by line before anything is sent: shared by
//! `polyturn device` and the web page's device panel.

use super::errors::{escaped, CliError, CliResult};
use crate::noncircular::table::{CamFile, FORMAT, STEPS_PER_MM};
use polyturn_sync::cam::CAM_POINTS;
use polyturn_sync::cam_upload::check_axis;
use polyturn_sync::console::tag::TAG_DIGITS;
use polyturn_sync::controller::check_table;

/// The firmware's line buffer (`polyturn_firmware::line::LINE_MAX`).
pub const DEVICE_LINE_MAX: usize = polyturn_firmware::line::LINE_MAX;
/// The longest command: the tag and its space take the rest.
pub const COMMAND_MAX: usize = DEVICE_LINE_MAX - TAG_DIGITS - 2;
/// A cam table file is a few tens of kB; more is not one (`/dev/zero`).
pub const CAM_FILE_MAX: u64 = 1 << 20;
/// The longest line taken from the device, without its CR LF (its replies
/// are at most `console::REPLY_LEN` plus the tag); anything longer is not
/// a polyturn.
pub const REPLY_MAX: usize = 512;
const _: () = assert!(polyturn_sync::console::REPLY_LEN + TAG_DIGITS + 2 <= REPLY_MAX);

/// The board's replies start `ok` (alone or with a space) or `error: `;
/// no command does, so neither an echo nor garbage passes for one. The
/// CLI's session and the page's (`web/www/js/serial.js`) both use it.
pub fn is_reply(line: &str) -> bool {
    line == "ok" || line.starts_with("ok ") || line.starts_with("error: ")
}

/// A command the board can take as one line: printable ASCII, not too long.
pub fn check_command(command: &str) -> CliResult<()> {
    if let Some(c) = command.chars().find(|c| c.is_control() || !c.is_ascii()) {
        return Err(CliError(format!(
            "the command '{}' holds {}: the board takes one line of plain ASCII",
            escaped(command),
            if c.is_control() { format!("a control character ({})", c.escape_default()) } else { format!("'{c}'") }
        )));
    }
    if command.len() > COMMAND_MAX {
        return Err(CliError(format!(
            "the command is {} characters long: the board takes at most {COMMAND_MAX}",
            command.len()
        )));
    }
    Ok(())
}

/// A `polyturn cam --table` file's text (`name` for the errors), checked:
/// its format, and that every line it sends is one console line.
pub fn cam_table(name: &str, text: &str) -> CliResult<CamFile> {
    if text.len() as u64 > CAM_FILE_MAX {
        return Err(CliError(format!(
            "upload-cam: '{name}' is larger than {CAM_FILE_MAX} bytes: not a polyturn cam table"
        )));
    }
    // the field at fault named by its path (`cutter.edges`, `points[3]`),
    // not only by its line and column
    let de = &mut serde_json::Deserializer::from_str(text);
    let table: CamFile = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let at = match e.path().to_string().as_str() {
            "." | "" => String::new(),
            p => format!("{p}: "),
        };
        CliError(format!("upload-cam: '{name}' is not a polyturn cam table: {at}{}", escaped(&e.inner().to_string())))
    })?;
    // one table a file: anything after it (a second table pasted on) is
    // refused, not left unsent
    de.end().map_err(|e| {
        CliError(format!(
            "upload-cam: '{name}' is not a polyturn cam table: it holds more after the table ({})",
            escaped(&e.to_string())
        ))
    })?;
    if table.format != FORMAT {
        return Err(CliError(format!(
            "upload-cam: '{name}' is format '{}', this polyturn sends '{}'",
            escaped(&table.format),
            FORMAT
        )));
    }
    declared(&table).map_err(|e| CliError(format!("upload-cam: '{name}' is refused: {e}")))?;
    // every line must go as one console line: checked before the port opens
    for line in table.upload_lines(COMMAND_MAX) {
        check_command(&line).map_err(|e| CliError(format!("upload-cam: '{name}' cannot be sent: {}", e.0)))?;
    }
    Ok(table)
}

/// What a table declares, checked before the port opens: its steps per mm
/// in `polyturn cam`'s range, its encoder in the console's `cpr` range,
/// and its X axis and points by the board's own rules (the sync core's
/// `check_axis` and `check_table`: the points against the X axis it
/// declares, `cam_upload::motion`). The board checks them again, and that
/// the encoder is its `cpr`.
fn declared(table: &CamFile) -> Result<(), String> {
    let (lo, hi) = STEPS_PER_MM;
    if !(lo..=hi).contains(&table.steps_per_mm) {
        return Err(format!("steps_per_mm must be a finite number >= {lo} and <= {hi} (got {:?})", table.steps_per_mm));
    }
    let cpr = table.counts_per_rev.to_string();
    polyturn_sync::Config::default()
        .with("cpr", &cpr)
        .map_err(|e| format!("counts_per_rev must be {} (the console's cpr; got {cpr})", e.allowed))?;
    if let Some(c) = &table.cutter {
        made_for(c)?;
        whole_passes(c, table)?;
    }
    axis_and_period(table)?;
    neighbours(&table.points)?;
    let h = table.header();
    check_axis(&h, polyturn_sync::Timing::FIRMWARE.tick_hz)?;
    check_table(&h, &table.points).map_err(|e| e.to_string())
}

/// The X axis, the period and the point count a table declares, each
/// refused naming its field and range: the board's own checks below
/// (`check_axis`, `Cam::check`) say the same in the console's words.
fn axis_and_period(table: &CamFile) -> Result<(), String> {
    let top = polyturn_sync::cam_upload::X_MAX_RATE_HZ;
    if !(1..=top).contains(&table.max_rate_hz) {
        return Err(format!(
            "max_rate_hz must be 1..={top} steps/s: the board emits at most one X step per two ticks (got {})",
            table.max_rate_hz
        ));
    }
    if table.max_accel == 0 {
        return Err(format!("max_accel must be 1..={} steps/s^2 (got 0)", u32::MAX));
    }
    let n = table.points.len();
    if !(2..=CAM_POINTS).contains(&n) {
        return Err(format!("points must hold 2..={CAM_POINTS} values (got {n})"));
    }
    if (table.period_counts as usize) < n {
        return Err(format!(
            "period_counts must be {n}..={} lathe counts: at least one for each of the {n} points (got {})",
            u32::MAX,
            table.period_counts
        ));
    }
    Ok(())
}

/// The first two neighbouring points (the last and the first too: the
/// table repeats) the board's interpolation cannot span (`Cam::wide_step`,
/// which `Cam::check` refuses with no index), named with their values.
fn neighbours(points: &[i32]) -> Result<(), String> {
    use polyturn_sync::cam::{Cam, STEP_SPAN};
    let Some(i) = Cam::wide_step(points) else { return Ok(()) };
    let j = (i + 1) % points.len();
    let wrap = if j == 0 { " (the last and the first: the table repeats)" } else { "" };
    Err(format!(
        "points[{i}] and points[{j}] must be less than {STEP_SPAN} (2^23) steps apart, the board's interpolation's range{wrap} (got {} and {})",
        points[i], points[j]
    ))
}

/// A compensating table's cutter as the console takes its settings: a
/// `ratio` and `edges` the board could be set to (else no board fits it).
fn made_for(c: &crate::noncircular::table::MadeFor) -> Result<(), String> {
    polyturn_sync::Ratio::parse(&c.ratio)
        .map_err(|e| format!("cutter.ratio {} (got '{}')", e.describe(), escaped(&c.ratio)))?;
    let edges = polyturn_sync::config::table::EDGES;
    edges.check(c.edges).map(|_| ()).map_err(|e| format!("cutter.edges must be {} (got {})", e.allowed, c.edges))
}

/// A compensating table repeats with its cutter's passes: its period is a
/// whole number of them (a pass is cpr x revolutions / sides counts of the
/// cutter's pattern), else each period the X motion slips against the
/// cutter (a period of 401 counts for a 400-count pass drifts a count a
/// pass).
fn whole_passes(c: &crate::noncircular::table::MadeFor, table: &CamFile) -> Result<(), String> {
    let Ok(ratio) = polyturn_sync::Ratio::parse(&c.ratio) else { return Ok(()) };
    let (sides, revolutions) = ratio.pattern(c.edges);
    let all = u64::from(revolutions) * u64::from(table.counts_per_rev);
    let least = all / polyturn_sync::ratio::gcd(all, u64::from(sides)).max(1);
    if least > 0 && u64::from(table.period_counts).is_multiple_of(least) {
        return Ok(());
    }
    Err(format!(
        "period_counts must be a whole number of the cutter's passes, a multiple of {least} counts for ratio {} with {} edges at {} counts a turn (got {})",
        escaped(&c.ratio),
        c.edges,
        table.counts_per_rev,
        table.period_counts
    ))
}

#[cfg(test)]
#[path = "console_line_tests.rs"]
mod tests;
