//! The board's serial port: where it is looked for when `--port` is not
//! given, and its opening, with a refusal that says what a path that is
//! not a serial port is (`/dev/null`, a file) rather than the OS's errno.

use super::super::errors::escaped;
use std::time::Duration;

/// What a missing `--port` gets, where the board was looked for.
#[cfg(not(windows))]
pub const NONE_FOUND: &str =
    "not given and no polyturn console found (looked for /dev/ttyACM*): connect the board by USB, or give --port PATH";
#[cfg(windows)]
pub const NONE_FOUND: &str = "not given and no polyturn console found (looked for USB 16c0:27dd among the COM ports): connect the board by USB, or give --port COM5 (its number in Device Manager, Ports)";

/// The polyturn console's USB IDs (firmware/src/app/usb.rs).
const CONSOLE_USB: (u16, u16) = (0x16c0, 0x27dd);

/// The board's console at `path`, 115 200 baud (the USB CDC-ACM ignores
/// it), reads returning every 50 ms so that a wait can keep its timeout.
pub fn open(path: &str) -> Result<Box<dyn serialport::SerialPort>, String> {
    serialport::new(path, 115_200).timeout(Duration::from_millis(50)).open().map_err(|e| {
        let shown = escaped(path);
        if not_a_terminal(path) {
            format!("{shown} is not a serial port (the board's console is {EXAMPLE})")
        } else {
            format!("cannot open {shown}: {e}")
        }
    })
}

#[cfg(not(windows))]
const EXAMPLE: &str = "a /dev/ttyACM* while it is plugged in";
#[cfg(windows)]
const EXAMPLE: &str = "a COM port, its number in Device Manager, Ports";

/// Whether `path` opens as a file that is no terminal: a serial port is a
/// terminal device (POSIX termios), `/dev/null` and regular files are not.
#[cfg(unix)]
fn not_a_terminal(path: &str) -> bool {
    use std::os::fd::AsRawFd;
    match std::fs::File::open(path) {
        // SAFETY: isatty reads the descriptor's type; the file is open.
        Ok(f) => unsafe { libc::isatty(f.as_raw_fd()) == 0 },
        Err(_) => false,
    }
}

/// Windows: a COM port's name is `COMn` or `\\.\COMn`; a path to a file is
/// not one.
#[cfg(not(unix))]
fn not_a_terminal(path: &str) -> bool {
    std::path::Path::new(path).is_file()
}

/// Windows names ports COMn: the console is the one with its USB IDs
/// (SetupAPI, through serialport's `available_ports`).
#[cfg(windows)]
pub fn find() -> Option<String> {
    first_console(serialport::available_ports().ok()?)
}

/// The first port that is the polyturn console by its USB IDs.
#[cfg_attr(not(windows), allow(dead_code))]
pub(super) fn first_console(ports: Vec<serialport::SerialPortInfo>) -> Option<String> {
    let mut found: Vec<String> = ports
        .into_iter()
        .filter(|p| matches!(&p.port_type, serialport::SerialPortType::UsbPort(u) if (u.vid, u.pid) == CONSOLE_USB))
        .map(|p| p.port_name)
        .collect();
    found.sort();
    found.into_iter().next()
}

/// The first USB CDC-ACM port, as Linux and macOS name them.
#[cfg(not(windows))]
pub fn find() -> Option<String> {
    let mut found: Vec<String> = std::fs::read_dir("/dev")
        .ok()?
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("ttyACM") || n.starts_with("cu.usbmodem"))
        .map(|n| format!("/dev/{n}"))
        .collect();
    found.sort();
    found.into_iter().next()
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn a_path_that_is_no_serial_port_is_named_as_such() {
        let Err(e) = open("/dev/null") else { panic!("/dev/null opened as a serial port") };
        assert_eq!(e, "/dev/null is not a serial port (the board's console is a /dev/ttyACM* while it is plugged in)");
        let file = std::env::temp_dir().join(format!("polyturn-port-{}", std::process::id()));
        std::fs::write(&file, b"").unwrap();
        let Err(e) = open(file.to_str().unwrap()) else { panic!("a file opened as a serial port") };
        std::fs::remove_file(&file).unwrap();
        assert!(
            e.ends_with("is not a serial port (the board's console is a /dev/ttyACM* while it is plugged in)"),
            "{e}"
        );
    }

    #[test]
    fn a_missing_port_keeps_the_systems_reason() {
        let Err(e) = open("/dev/polyturn-no-such-port") else { panic!("a missing port opened") };
        assert!(e.starts_with("cannot open /dev/polyturn-no-such-port: "), "{e}");
    }
}
