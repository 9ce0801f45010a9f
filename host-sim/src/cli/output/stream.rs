//! Writing a FIFO or a character device in place, bounded in time: a FIFO
//! is opened without blocking (O_NONBLOCK: with no reader the open fails
//! at once with ENXIO, fifo(7)), tried again until a reader comes or
//! `wait` runs out; then written without blocking, waiting for room
//! (poll(2), POLLOUT) at most `wait` at a time.

use std::io::{Error, ErrorKind, Write};
use std::path::Path;
use std::time::{Duration, Instant};

/// How often a FIFO is tried again while it has no reader.
const RETRY: Duration = Duration::from_millis(20);

/// Writes all of `bytes` to the FIFO or device at `path`.
#[cfg(unix)]
pub fn write(path: &Path, bytes: &[u8], wait: Duration) -> std::io::Result<()> {
    let mut f = open(path, wait)?;
    let mut rest = bytes;
    while !rest.is_empty() {
        match f.write(rest) {
            Ok(0) => return Err(Error::new(ErrorKind::WriteZero, "the reader took nothing")),
            Ok(n) => rest = &rest[n..],
            Err(e) if e.kind() == ErrorKind::WouldBlock => room(&f, wait)?,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

#[cfg(not(unix))]
pub fn write(path: &Path, bytes: &[u8], _wait: Duration) -> std::io::Result<()> {
    let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
    f.write_all(bytes)?;
    f.flush()
}

#[cfg(unix)]
fn open(path: &Path, wait: Duration) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    let deadline = Instant::now() + wait;
    loop {
        match std::fs::OpenOptions::new().write(true).custom_flags(libc::O_NONBLOCK).open(path) {
            Err(e) if e.raw_os_error() == Some(libc::ENXIO) => {
                if Instant::now() >= deadline {
                    let why = format!("no reader opened the FIFO within {} s", seconds(wait));
                    return Err(Error::new(ErrorKind::TimedOut, why));
                }
                std::thread::sleep(RETRY);
            }
            other => return other,
        }
    }
}

/// Waits until `f` takes bytes again, at most `wait`.
#[cfg(unix)]
fn room(f: &std::fs::File, wait: Duration) -> std::io::Result<()> {
    use std::os::fd::AsRawFd;
    let mut p = libc::pollfd { fd: f.as_raw_fd(), events: libc::POLLOUT, revents: 0 };
    let ms = wait.as_millis().min(i32::MAX as u128) as i32;
    // SAFETY: one pollfd, valid for the call
    match unsafe { libc::poll(&mut p, 1, ms) } {
        0 => Err(Error::new(ErrorKind::TimedOut, format!("the reader took nothing for {} s", seconds(wait)))),
        n if n < 0 => Err(Error::last_os_error()),
        _ => Ok(()),
    }
}

/// 0.2, 10: a duration as a message gives it.
fn seconds(d: Duration) -> String {
    format!("{}", d.as_millis() as f64 / 1000.0)
}
