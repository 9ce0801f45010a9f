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
/// What is not a device (a FIFO, a file, a folder) is refused before it
/// is opened: opening a FIFO waits for a writer, with no timeout.
pub fn open(path: &str) -> Result<Box<dyn serialport::SerialPort>, String> {
    let not_serial = || format!("{} is not a serial port (the board's console is {EXAMPLE})", escaped(path));
    if not_a_device(path) {
        return Err(not_serial());
    }
    serialport::new(path, 115_200).timeout(Duration::from_millis(50)).open().map_err(|e| {
        if not_a_terminal(path) {
            not_serial()
        } else {
            format!("cannot open {}: {e}", escaped(path))
        }
    })
}

/// Whether `path` exists and is no character device (POSIX: a terminal
/// is one; a FIFO, a regular file or a folder is not).
#[cfg(unix)]
fn not_a_device(path: &str) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::metadata(path).is_ok_and(|m| !m.file_type().is_char_device())
}

#[cfg(not(unix))]
fn not_a_device(path: &str) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.is_file() || m.is_dir())
}

#[cfg(not(windows))]
const EXAMPLE: &str = "a /dev/ttyACM* while it is plugged in";
#[cfg(windows)]
const EXAMPLE: &str = "a COM port, its number in Device Manager, Ports";

/// Whether the character device at `path` is no terminal: a serial port
/// is one (POSIX termios), `/dev/null` is not. Opened without waiting
/// (O_NONBLOCK) and without becoming the controlling terminal.
#[cfg(unix)]
fn not_a_terminal(path: &str) -> bool {
    use std::os::fd::AsRawFd;
    use std::os::unix::fs::OpenOptionsExt;
    let opened = std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY).open(path);
    match opened {
        // SAFETY: isatty reads the descriptor's type; the file is open.
        Ok(f) => unsafe { libc::isatty(f.as_raw_fd()) == 0 },
        Err(_) => false,
    }
}

/// Windows: what is not a device was refused before the open.
#[cfg(not(unix))]
fn not_a_terminal(_path: &str) -> bool {
    false
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
    fn a_fifo_is_refused_at_once_not_waited_on() {
        let fifo = std::env::temp_dir().join(format!("polyturn-fifo-{}", std::process::id()));
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: mkfifo reads the NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let (tx, rx) = std::sync::mpsc::channel();
        let path = fifo.to_str().unwrap().to_string();
        std::thread::spawn(move || tx.send(open(&path).err()));
        let got = rx.recv_timeout(std::time::Duration::from_secs(5));
        std::fs::remove_file(&fifo).unwrap();
        let e = got.expect("opening a FIFO waited").expect("a FIFO opened as a serial port");
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
