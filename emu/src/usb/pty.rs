//! `--pty`: the console of the real image on a pseudo-terminal. Boots, enumerates
//! (as the scenario does), opens a pty (openpty(3)), prints the path of its
//! terminal side on stdout, then bridges: bytes written to the terminal go out on
//! the CDC bulk OUT endpoint, bytes from bulk IN come back, while the emulator
//! runs 1 ms at a time (slower than real time: the firmware's timers run on
//! emulated time). `polyturn device --port PATH status` then talks to the image.
//! `--lathe-rpm RPM` turns the lathe (its encoder on PA6/PA7/PB0) at that speed.

use super::scenario;
use crate::image::Image;
use crate::job::lathe::LatheDrive;
use polyturn_host::sim::lathe::{LatheProfile, Leg};
use std::rc::Rc;
use std::time::Duration;

/// The pty's controller side (non-blocking) and its terminal side, kept open so
/// reads do not fail while no client has it open.
struct Pty {
    master: libc::c_int,
    slave: libc::c_int,
}

impl Drop for Pty {
    fn drop(&mut self) {
        // SAFETY: both fds are this struct's own, closed once
        unsafe {
            libc::close(self.master);
            libc::close(self.slave);
        }
    }
}

fn open() -> Result<(Pty, String), String> {
    let (mut master, mut slave) = (-1, -1);
    let mut name = [0 as libc::c_char; 128];
    // SAFETY: openpty only writes the two fds (the name is not asked for: it is
    // fetched with ttyname_r into a sized buffer below)
    let r = unsafe { libc::openpty(&mut master, &mut slave, std::ptr::null_mut(), std::ptr::null(), std::ptr::null()) };
    if r != 0 {
        return Err(format!("openpty: {}", std::io::Error::last_os_error()));
    }
    let pty = Pty { master, slave }; // closed on every return from here
                                     // SAFETY: `name` is a valid buffer of the length passed; the fds are ours
    unsafe {
        if libc::ttyname_r(slave, name.as_mut_ptr(), name.len()) != 0 {
            return Err("ttyname_r failed".into());
        }
        let mut t: libc::termios = std::mem::zeroed();
        if libc::tcgetattr(slave, &mut t) == 0 {
            libc::cfmakeraw(&mut t);
            libc::tcsetattr(slave, libc::TCSANOW, &t);
        }
        let fl = libc::fcntl(master, libc::F_GETFL);
        libc::fcntl(master, libc::F_SETFL, fl | libc::O_NONBLOCK);
    }
    let path = name.iter().take_while(|&&c| c != 0).map(|&c| c as u8 as char).collect();
    Ok((pty, path))
}

impl Pty {
    /// What the client wrote, up to `buf`'s length (empty if nothing).
    fn read(&self, buf: &mut [u8]) -> usize {
        // SAFETY: reads at most buf.len() bytes into buf
        let n = unsafe { libc::read(self.master, buf.as_mut_ptr().cast(), buf.len()) };
        n.max(0) as usize
    }

    /// Writes all of `data`, waiting while the pty's buffer is full.
    fn write(&self, mut data: &[u8]) {
        while !data.is_empty() {
            // SAFETY: writes at most data.len() bytes from data
            let n = unsafe { libc::write(self.master, data.as_ptr().cast(), data.len()) };
            if n > 0 {
                data = &data[n as usize..];
            } else {
                std::thread::sleep(Duration::from_millis(1));
            }
        }
    }
}

/// The host simulator's motor holding `rpm` from the start (no ripple, no
/// wander), for as long as the emulator runs.
fn turning(rpm: f64, cpr: u32, now: u64) -> LatheDrive {
    let hold = Leg { rpm, accel_rpm_per_s: 1000.0, hold_s: 1e9 };
    let profile = LatheProfile { start_rpm: rpm, legs: vec![hold], ripple: 0.0, wander: 0.0, dips: vec![] };
    LatheDrive::motor(profile, 1, cpr, now, crate::MS * 1000)
}

pub fn serve(image: &Rc<Image>, lathe_rpm: Option<f64>) -> Result<(), String> {
    let (mut m, en_ms, en_wall) = scenario::enumerate(image)?;
    if let Some(rpm) = lathe_rpm {
        let now = m.chip().now;
        m.lathe = Some(turning(rpm, m.cpr, now));
        eprintln!("emu: the lathe turns at {rpm} rpm");
    }
    let (pty, path) = open()?;
    println!("{path}");
    eprintln!("emu: enumerated at {en_ms:.1} ms emulated ({en_wall:.2} s wall); {path} is the console (Ctrl-C ends)");
    let mut buf = [0u8; 256];
    let mut pending: Vec<u8> = Vec::new();
    loop {
        if pending.is_empty() {
            let n = pty.read(&mut buf);
            pending.extend_from_slice(&buf[..n]);
        }
        if !pending.is_empty() && scenario::host(&mut m).send(&pending) {
            pending.clear();
        }
        m.run(crate::MS);
        let out = scenario::host(&mut m).received();
        pty.write(&out);
        if let Some(e) = scenario::host(&mut m).error() {
            return Err(e.to_string());
        }
        if !m.chip().faults.is_empty() {
            return Err(crate::checks::faults(&mut m));
        }
    }
}

#[cfg(test)]
mod tests {
    use std::io::{Read, Write};

    #[test]
    fn the_lathe_flag_turns_the_encoder_at_its_speed_from_the_start() {
        let sysclk = crate::MS * 1000;
        let mut l = super::turning(300.0, 2400, 0);
        // 0.2 s at 300 rpm: one turn, 2400 counts
        let end = sysclk / 5;
        while l.next_edge(end).is_some_and(|at| at <= end) {
            l.take_due(end);
        }
        assert!((l.count - 2400).abs() <= 2, "{} counts in 0.2 s", l.count);
        assert!(!l.finished(), "it keeps turning");
    }

    #[test]
    fn bytes_cross_the_pty_both_ways_unechoed() {
        let (pty, path) = super::open().expect("openpty");
        let mut term = std::fs::OpenOptions::new().read(true).write(true).open(&path).expect("the terminal side");
        term.write_all(b"status\n").unwrap();
        let mut buf = [0u8; 32];
        let mut n = 0;
        for _ in 0..100 {
            n = pty.read(&mut buf);
            if n > 0 {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert_eq!(&buf[..n], b"status\n", "raw: no line-discipline translation");
        pty.write(b"ok\r\n");
        let mut back = [0u8; 4];
        term.read_exact(&mut back).unwrap();
        assert_eq!(&back, b"ok\r\n");
        assert_eq!(pty.read(&mut buf), 0, "nothing echoed back");
    }
}
