//! `polyturn device ...`: the firmware's console protocol over a serial port
//! (the Black Pill's USB CDC-ACM console), one tagged line out, the line
//! with the same tag back (`session.rs`).

pub mod checks;
pub mod divide;
#[cfg(test)]
mod divide_tests;
pub use super::figures;
pub mod port;
pub mod prompt;
#[cfg(test)]
mod selftest_tests;
pub mod session;
pub mod setup;
#[cfg(test)]
mod tests;

use super::errors::{escaped, CliError, CliResult};
use super::values::within;
use polyturn_sync::config::table::DIVIDE;
use session::{ok_or_device_error, Session, Wait};
use std::io::{IsTerminal, Read, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pub use super::console_line::CAM_FILE_MAX;
/// An erase of the settings sector takes up to 2 s at x32 (DS10314
/// Table 27 t_ERASE128KB max): `save` and a table's last line wait longer.
pub(crate) const FLASH_WAIT: Duration = Duration::from_secs(10);

#[derive(clap::Args, Debug)]
#[command(disable_help_subcommand = true)]
pub struct DeviceArgs {
    /// The board's serial port [default: the first /dev/ttyACM* or /dev/cu.usbmodem*]
    #[arg(long, global = true, value_name = "PATH")]
    pub port: Option<String>,
    /// How long to wait for each reply, seconds (`save` and a table's last line
    /// wait at least 10: erasing the settings' flash sector takes up to 2 s)
    #[arg(long, global = true, value_name = "S", default_value = "3", allow_hyphen_values = true, value_parser = within(0.01, 60.0, "s"))]
    pub timeout: f64,
    #[command(subcommand)]
    pub command: DeviceCommand,
}

#[derive(clap::Subcommand, Debug)]
pub enum DeviceCommand {
    /// State, lathe rpm, phase error and fault, once
    Status,
    /// Status five times a second until Ctrl-C
    Watch,
    /// One setting, or all of them
    Get {
        /// the setting [default: all of them]
        #[arg(value_parser = setting_name())]
        name: Option<String>,
    },
    /// Change a setting (checked by the board; `save` keeps it)
    Set {
        /// the setting
        #[arg(value_parser = setting_name())]
        name: String,
        /// its new value (negative numbers are taken as values)
        #[arg(allow_hyphen_values = true)]
        value: String,
    },
    /// Start the cutter in sync with the lathe
    Engage,
    /// Ramp the cutter down and stop
    Stop,
    /// Clear a fault
    Clear,
    /// Write the settings to flash (idle, lathe at rest)
    Save,
    /// Restore the default settings (not saved)
    Defaults,
    /// The board's own command list
    #[command(name = "help")]
    ConsoleHelp,
    /// Send a cam table made by `polyturn cam --table FILE` or `polyturn compensate --table FILE`
    UploadCam {
        /// the table file (JSON)
        file: PathBuf,
    },
    /// Remove the board's cam table (the X axis off; `save` to forget it):
    /// before a table for another cutter, or to change ratio, edges or drive
    CamOff,
    /// Measure the lathe encoder while you turn the chuck: real counts per
    /// turn, direction, lost counts, chatter; proposes `set cpr`
    CheckEncoder {
        /// No index pulse: count over this many chuck turns (from a mark)
        #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = crate::cli::values::whole32(1, 100))]
        turns: Option<u32>,
        /// Measure for this long instead of until Enter, s (lathe running slowly)
        #[arg(long, value_name = "S", allow_hyphen_values = true, value_parser = within(0.01, 600.0, "s"))]
        seconds: Option<f64>,
    },
    /// Turn the cutter by an angle, slowly (30 rpm), lathe at rest: check
    /// its direction and that one commanded turn is one real turn
    Jog {
        /// degrees of the cutter, -3600..=3600, up to 3 decimals (360 = one turn)
        #[arg(allow_hyphen_values = true, value_parser = checks::jog_degrees)]
        degrees: String,
    },
    /// The bench self-test (lathe encoder unplugged; jumpers PA2-PA6,
    /// PA3-PA7, PA4-PB0, PB14 to GND): the board plays a lathe into its own
    /// inputs and checks its gearbox against it; pass or fail with figures
    Selftest {
        /// speed of the holds, lathe rpm (default 300, capped by the board)
        #[arg(long, value_name = "RPM", allow_hyphen_values = true, value_parser = crate::cli::values::whole32(1, 100_000))]
        rpm: Option<u32>,
    },
    /// Dividing: turn the chuck by hand to N equal divisions of a turn,
    /// with a live readout of the nearest division and how far to turn to
    /// it (large digits, green within a count) until Ctrl-C; the cutter
    /// stays off
    Divide {
        /// divisions of a turn
        #[arg(allow_hyphen_values = true, value_parser = crate::cli::values::setting(DIVIDE))]
        divisions: u32,
    },
    /// Restart the board into its ROM USB bootloader, for `polyturn flash`
    Dfu,
    /// The guided setup: encoder, motor, driver, lathe; checks; save
    Setup(setup::GuidedArgs),
}

impl DeviceCommand {
    /// The console line, or None for the upload.
    fn line(&self) -> Option<String> {
        Some(match self {
            DeviceCommand::Status => "status".into(),
            DeviceCommand::Watch => "watch".into(),
            DeviceCommand::Get { name: None } => "get".into(),
            DeviceCommand::Get { name: Some(n) } => format!("get {n}"),
            DeviceCommand::Set { name, value } => format!("set {name} {value}"),
            DeviceCommand::Engage => "engage".into(),
            DeviceCommand::Stop => "stop".into(),
            DeviceCommand::Clear => "clear".into(),
            DeviceCommand::Save => "save".into(),
            DeviceCommand::Defaults => "defaults".into(),
            DeviceCommand::ConsoleHelp => "help".into(),
            DeviceCommand::Dfu => "dfu".into(),
            DeviceCommand::CamOff => "cam off".into(),
            DeviceCommand::Jog { degrees } => format!("jog {degrees}"),
            DeviceCommand::Divide { divisions } => format!("divide {divisions}"),
            DeviceCommand::Selftest { rpm: None } => "selftest start".into(),
            DeviceCommand::Selftest { rpm: Some(r) } => format!("selftest start {r}"),
            DeviceCommand::UploadCam { .. } | DeviceCommand::CheckEncoder { .. } | DeviceCommand::Setup(_) => {
                return None
            }
        })
    }
}

pub fn run(a: DeviceArgs) -> CliResult<String> {
    // Everything that can be refused without the board is refused first.
    let line = a.command.line();
    if let Some(l) = &line {
        session::check_command(l)?;
    }
    if let DeviceCommand::Setup(g) = &a.command {
        if g.non_interactive {
            crate::cli::guided::from_flags(g)?;
        }
    }
    let table = match &a.command {
        DeviceCommand::UploadCam { file } => Some(read_table(file)?),
        _ => None,
    };
    let path = a.port.clone().or_else(port::find).ok_or_else(|| CliError::flag("port", port::NONE_FOUND))?;
    let serial = port::open(&path).map_err(|why| CliError::flag("port", why))?;
    let mut s = Session::new(serial, &path, Duration::from_secs_f64(a.timeout));
    match (&a.command, line) {
        (DeviceCommand::Watch, _) => watch(&mut s, &mut std::io::stdout().lock()),
        (DeviceCommand::Save, Some(l)) => ok_or_device_error(s.ask_within(&l, FLASH_WAIT.max(s.timeout))?),
        (DeviceCommand::Jog { degrees }, _) => checks::jog(&mut s, degrees),
        (DeviceCommand::Selftest { .. }, Some(l)) => checks::selftest(&mut s, &l),
        (DeviceCommand::Divide { .. }, Some(l)) => {
            let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
            let look = if std::io::stdout().is_terminal() { divide::Look::Big } else { divide::Look::Plain };
            divide::divide(&mut s, &l, &mut std::io::stdout().lock(), &INTERRUPTED, look)
        }
        (DeviceCommand::Dfu, Some(l)) => Ok(format!(
            "{}
now: polyturn flash FILE",
            s.ask(&l)?
        )),
        (DeviceCommand::CheckEncoder { turns, seconds }, _) => {
            let turning =
                seconds.map_or(checks::Turning::UntilEnter, |t| checks::Turning::For(Duration::from_secs_f64(t)));
            let (f, proposal) =
                checks::check_encoder(&mut s, &mut prompt::Terminal::with_ctrl_c("check-encoder"), turning, *turns)?;
            let text = checks::explain(&f, &proposal, *turns);
            // a check that proposes no cpr failed: a script must see it
            match proposal {
                Ok(_) => Ok(text),
                Err(_) => Err(CliError(format!("device: the encoder check proposes no cpr:\n{text}"))),
            }
        }
        (DeviceCommand::Setup(args), _) => setup::run(&mut s, args, &mut prompt::Terminal::with_ctrl_c("setup")),
        (DeviceCommand::UploadCam { .. }, _) => upload(&mut s, table.as_ref().expect("read above")),
        (_, Some(l)) => s.ask(&l),
        (_, None) => Err(CliError("internal: a device command without a line".into())),
    }
}

/// A setting's name: the console's table of settings lists them (its
/// `get` order), so `--help` shows each and a name the console does not
/// have is refused before any port is opened.
fn setting_name() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(polyturn_sync::config::NAMES)
}

/// Set by Ctrl-C during a watch.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Prints status lines until Ctrl-C (or the reader goes away), then ends
/// the watch on the board with a tagged `status` and waits for its reply,
/// so the board is back to one reply per command when we return.
pub fn watch<P: Read + Write>(s: &mut Session<P>, out: &mut impl Write) -> CliResult<String> {
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
    stream(s, out, &INTERRUPTED, escaped)?;
    Ok(String::new())
}

/// The board's status lines (`watch`), each written as `show` makes it,
/// until `stop` is set or the reader goes away; then the watch is ended
/// on the board (a tagged `status`, answered).
pub fn stream<P: Read + Write>(
    s: &mut Session<P>,
    out: &mut impl Write,
    stop: &AtomicBool,
    mut show: impl FnMut(&str) -> String,
) -> CliResult<()> {
    let mut line = s.ask("watch")?;
    loop {
        if writeln!(out, "{}", show(&line)).and_then(|_| out.flush()).is_err() {
            break; // the reader went away (a closed pipe)
        }
        match next_status(s, stop)? {
            Some(l) => line = l,
            None => break,
        }
    }
    s.ask("status")?;
    Ok(())
}

/// The next status line of a watch, waited for in short slices to see
/// `stop`; None once it is set.
fn next_status<P: Read + Write>(s: &mut Session<P>, stop: &AtomicBool) -> CliResult<Option<String>> {
    let deadline = Instant::now() + s.timeout;
    loop {
        if stop.load(Ordering::SeqCst) {
            return Ok(None);
        }
        match s.read_line(Instant::now() + Duration::from_millis(100)) {
            Ok(l) if l.starts_with("ok state=") => return Ok(Some(l)),
            Ok(_) if Instant::now() < deadline => continue,
            Err(Wait::Timeout) if Instant::now() < deadline => continue,
            Ok(_) | Err(Wait::Timeout) => {
                return Err(
                    s.port_error(format!("the watch stopped: no status within {:.1} s", s.timeout.as_secs_f64()))
                )
            }
            Err(Wait::Closed(why)) => return Err(s.closed("watch", &why)),
            Err(Wait::Failed(e)) => return Err(e),
        }
    }
}

/// Reads and checks a `polyturn cam --table` file (bounded in size),
/// before the port is opened. Only a regular file: a FIFO would wait for
/// its writer, a device never end. Opened without blocking (a FIFO's open
/// waits for a writer otherwise), then refused by what it is.
fn read_table(file: &std::path::Path) -> CliResult<crate::noncircular::table::CamFile> {
    let name = escaped(&file.display().to_string());
    let mut open = std::fs::OpenOptions::new();
    open.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut open, libc::O_NONBLOCK);
    let f = open.open(file).map_err(|e| CliError(format!("upload-cam: cannot read '{name}': {e}")))?;
    if !f.metadata().is_ok_and(|m| m.is_file()) {
        return Err(CliError(format!(
            "FILE must be a regular file, the table `polyturn cam --table` writes (got '{name}': not a regular file)"
        )));
    }
    let mut text = String::new();
    f.take(CAM_FILE_MAX + 1)
        .read_to_string(&mut text)
        .map_err(|e| CliError(format!("upload-cam: cannot read '{name}' as text: {e}")))?;
    super::console_line::cam_table(&name, &text)
}

/// A table fits only the encoder and the tool it was made for: a
/// compensating table the ratio, edges and sense of its cutter, a single-point
/// tool's no cutter at all.
/// Refused, naming what differs and sending nothing, when the board's differ.
fn same_tool<P: Read + Write>(s: &mut Session<P>, table: &crate::noncircular::table::CamFile) -> CliResult<()> {
    let mut setting = |name: &str| -> CliResult<String> {
        let reply = ok_or_device_error(s.ask(&format!("get {name}"))?)?;
        Ok(reply.split_once('=').map(|(_, v)| v.trim().to_string()).unwrap_or_default())
    };
    let (cpr, ratio, edges, drive) = (setting("cpr")?, setting("ratio")?, setting("edges")?, setting("drive")?);
    let dir = setting("dir")?;
    let board = crate::noncircular::table::Board { cpr: &cpr, ratio: &ratio, edges: &edges, drive: &drive, dir: &dir };
    table.fits(&board).map_err(|e| CliError(format!("upload-cam: {e}")))
}

/// Sends a table line by line; stops at the first error (the device then
/// discards the partial table). The last line saves to flash: it waits
/// as long as a save.
pub fn upload<P: Read + Write>(s: &mut Session<P>, table: &crate::noncircular::table::CamFile) -> CliResult<String> {
    same_tool(s, table)?;
    send_table(s, table)
}

/// `upload` without the tool's check: the board's own checks answer.
pub(crate) fn send_table<P: Read + Write>(
    s: &mut Session<P>,
    table: &crate::noncircular::table::CamFile,
) -> CliResult<String> {
    let lines = table.upload_lines(super::console_line::COMMAND_MAX);
    let mut last = String::new();
    for (i, line) in lines.iter().enumerate() {
        let wait = if i + 1 == lines.len() { FLASH_WAIT.max(s.timeout) } else { s.timeout };
        last = ok_or_device_error(s.ask_within(line, wait)?).map_err(kept_for_another_try)?;
    }
    Ok(last)
}

/// The board keeps a complete table it could not save for a `cam end`
/// sent again; this command sends the whole table again instead.
fn kept_for_another_try(e: CliError) -> CliError {
    CliError(e.0.replace("send cam end again", "run upload-cam again to send it"))
}
