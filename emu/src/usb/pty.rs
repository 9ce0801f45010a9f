//! `--pty`: the console of the real image on a pseudo-terminal. Boots, enumerates
//! (as the scenario does), opens a pty (openpty(3)), prints the path of its
//! terminal side on stdout, then bridges: bytes written to the terminal go out on
//! the CDC bulk OUT endpoint, bytes from bulk IN come back, while the emulator
//! runs 1 ms at a time (slower than real time: the firmware's timers run on
//! emulated time). `polyturn device --port PATH status` then talks to the image.
//! `--lathe-rpm RPM` turns the lathe (its encoder on PA6/PA7/PB0) at that speed.
//!
//! The board resets as silicon does, keeping its flash: when the image asks
//! (SCB AIRCR.SYSRESETREQ), when the watchdog runs out, or on SIGUSR1 (the
//! NRST button); one line on stderr says why, the machine boots again,
//! enumerates again (a second line says so), and the same pty serves on.
//! A real board drops off USB at a reset: what the client wrote that the
//! board had not taken, before or during the reset, is dropped, never
//! executed by the rebooted image. The lathe keeps turning. If the image
//! jumps to ST's ROM bootloader (after `dfu`), which is not here, serving
//! ends: [`Stop::Bootloader`].
//!
//! Clients come and go (each `polyturn device` opens the terminal and
//! closes it): a new client never reads what an earlier one left unread,
//! and output while nobody has the terminal open is dropped.

use super::scenario;
use crate::chip::pins::Outputs;
use crate::image::Image;
use crate::job::lathe::LatheDrive;
use crate::machine::{Machine, Reset};
use polyturn_host::sim::lathe::{LatheProfile, Leg};
use polyturn_stm32_model::chip::iwdg::LSI_HZ;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

mod clients;

/// The pty's controller side (non-blocking) and its terminal side, kept open so
/// reads do not fail while no client has it open; who else has it open.
struct Pty {
    master: libc::c_int,
    slave: libc::c_int,
    clients: clients::Clients,
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
    // closed on every return from here
    let mut pty = Pty { master, slave, clients: clients::Clients::everyone() };
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
    let path: String = name.iter().take_while(|&&c| c != 0).map(|&c| c as u8 as char).collect();
    pty.clients = clients::Clients::watch(&path);
    Ok((pty, path))
}

impl Pty {
    /// What the client wrote, up to `buf`'s length (empty if nothing).
    fn read(&self, buf: &mut [u8]) -> usize {
        // SAFETY: reads at most buf.len() bytes into buf
        let n = unsafe { libc::read(self.master, buf.as_mut_ptr().cast(), buf.len()) };
        n.max(0) as usize
    }

    /// The device's output, to whoever has the terminal open now. What a
    /// client left unread is dropped when it leaves (the last one) or
    /// another arrives, so a new client finds nothing of an earlier one's
    /// (a real board's port has no such past: the host's driver reads a
    /// CDC port only while it is open); with no client the output goes
    /// nowhere. A drop of anything is said on stderr.
    fn deliver(&mut self, data: &[u8]) {
        let seen = self.clients.seen();
        if seen.arrived || seen.emptied {
            let mut unread: libc::c_int = 0;
            // SAFETY: our own terminal fd: how much it holds, then drop it
            unsafe {
                libc::ioctl(self.slave, libc::FIONREAD, &mut unread);
                libc::tcflush(self.slave, libc::TCIFLUSH);
            }
            if unread > 0 {
                eprintln!("emu: {unread} bytes a client of the console left unread were dropped");
            }
        }
        if seen.open > 0 {
            self.write(data);
        }
    }

    /// Drops what the host wrote and the board has not taken: the board's
    /// reset takes it off the bus, and what was on its way is lost. Returns
    /// how many bytes.
    fn drop_input(&self) -> usize {
        let mut buf = [0u8; 256];
        let mut dropped = 0;
        // bounded: a client writing without end gets 1 MiB dropped a call
        for _ in 0..4096 {
            let n = self.read(&mut buf);
            if n == 0 {
                break;
            }
            dropped += n;
        }
        dropped
    }

    /// Writes all of `data`, waiting while the pty's buffer is full, at most
    /// a second without progress (a client that never reads): the rest is
    /// dropped, as a full host buffer drops it.
    fn write(&self, mut data: &[u8]) {
        let mut idle_ms = 0;
        while !data.is_empty() && idle_ms < 1000 {
            // SAFETY: writes at most data.len() bytes from data
            let n = unsafe { libc::write(self.master, data.as_ptr().cast(), data.len()) };
            if n > 0 {
                data = &data[n as usize..];
                idle_ms = 0;
            } else {
                std::thread::sleep(Duration::from_millis(1));
                idle_ms += 1;
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

/// Set by SIGUSR1: the board's NRST button, pressed by hand (`kill -USR1 PID`).
static NRST: AtomicBool = AtomicBool::new(false);

extern "C" fn on_usr1(_: libc::c_int) {
    NRST.store(true, Ordering::SeqCst);
}

/// How serving ends: it only ends when the image leaves for ST's ROM
/// bootloader (`dfu`), or on a failure.
pub enum Stop {
    /// the image jumped to the ROM bootloader: the outputs when it asked for
    /// the reset before the jump (none if no software reset came first)
    Bootloader {
        at_request: Option<Outputs>,
    },
    Failed(String),
}

impl From<String> for Stop {
    fn from(e: String) -> Stop {
        Stop::Failed(e)
    }
}

pub fn serve(image: &Rc<Image>, lathe_rpm: Option<f64>) -> Stop {
    match bridge(image, lathe_rpm) {
        Ok(never) => match never {},
        Err(stop) => stop,
    }
}

fn bridge(image: &Rc<Image>, lathe_rpm: Option<f64>) -> Result<std::convert::Infallible, Stop> {
    let (mut m, en_ms, en_wall) = scenario::enumerate(image)?;
    if let Some(rpm) = lathe_rpm {
        let now = m.chip().now;
        m.lathe = Some(turning(rpm, m.cpr, now));
        eprintln!("emu: the lathe turns at {rpm} rpm");
    }
    let (mut pty, path) = open()?;
    // SAFETY: the handler only stores to an atomic, which is async-signal-safe
    unsafe { libc::signal(libc::SIGUSR1, on_usr1 as extern "C" fn(libc::c_int) as libc::sighandler_t) };
    println!("{path}");
    eprintln!("emu: enumerated at {en_ms:.1} ms emulated ({en_wall:.2} s wall); {path} is the console (Ctrl-C ends; kill -USR1 {} presses NRST)", std::process::id());
    let mut buf = [0u8; 256];
    let mut pending: Vec<u8> = Vec::new();
    loop {
        // a reset first, before the host's next bytes are taken: they never
        // reach the board that reset
        let why = if NRST.swap(false, Ordering::SeqCst) { Some(Reset::Pin) } else { m.reset_due() };
        if let Some(why) = why {
            // the outputs as the image left them when it asked: `dfu` turns them off first
            let at_request = (why == Reset::Software).then(|| m.chip().outputs());
            m = reboot(m, &why, at_request)?;
            // the board left the bus: what the host had not delivered is lost
            let dropped = pending.len() + pty.drop_input();
            pending.clear();
            let t = m.chip().now as f64 / crate::MS as f64;
            eprintln!("emu: enumerated again at {t:.1} ms emulated; {dropped} bytes the host had not delivered before the reset were dropped");
            continue;
        }
        if pending.is_empty() {
            let n = pty.read(&mut buf);
            pending.extend_from_slice(&buf[..n]);
        }
        if !pending.is_empty() && scenario::host(&mut m).send(&pending) {
            pending.clear();
        }
        m.run(crate::MS);
        let out = scenario::host(&mut m).received();
        pty.deliver(&out);
        if let Some(e) = scenario::host(&mut m).error() {
            return Err(e.to_string().into());
        }
        if !m.chip().faults.is_empty() {
            return Err(crate::checks::faults(&mut m).into());
        }
    }
}

/// The chip resets, keeping its flash, and enumerates again on the same cable;
/// the pty stays open, so the client's path still serves.
fn reboot(mut m: Machine, why: &Reset, at_request: Option<Outputs>) -> Result<Machine, Stop> {
    let t = m.chip().now as f64 / crate::MS as f64;
    let since = flash_and_watchdog(&mut m);
    eprintln!("emu: reset at {t:.1} ms emulated: {why}; the flash kept, the same pty serving; since boot {since}");
    let (mut m, r) = scenario::enumerate_keeping(m.reset_as(why)?);
    if m.chip().rom_jump {
        return Err(Stop::Bootloader { at_request });
    }
    r?;
    Ok(m)
}

/// Since boot: the CPU's stall by flash operations, and the watchdog's longest
/// gap between reloads against its shortest timeout; what a save must show.
fn flash_and_watchdog(m: &mut Machine) -> String {
    let c = m.chip();
    let ms = |cycles: u64| cycles / crate::MS;
    let gap = c.iwdg.longest_gap(c.iwdg.started_at().unwrap_or(c.now), c.now);
    let shortest = c.iwdg.timeout_ns(LSI_HZ[2]) / 1_000_000;
    format!(
        "the flash stalled the CPU {} ms; longest watchdog gap {} ms (shortest timeout {shortest} ms)",
        ms(c.stalled),
        ms(gap)
    )
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
    fn across_a_reset_the_lathe_keeps_its_pace() {
        // one lathe turned 0.2 s straight; another whose CPU count restarts
        // (a reset) at 0.1 s: the same count at the same moment of the wall
        let (sysclk, tenth) = (crate::MS * 1000, crate::MS * 100);
        let run = |l: &mut super::LatheDrive, end: u64| {
            while l.next_edge(end).is_some_and(|at| at <= end) {
                l.take_due(end);
            }
        };
        let mut straight = super::turning(300.0, 2400, 0);
        run(&mut straight, sysclk / 5);
        let mut reset = super::turning(300.0, 2400, 0);
        run(&mut reset, tenth);
        reset.rebase(tenth);
        run(&mut reset, tenth);
        assert!(straight.count > 2300, "{}", straight.count);
        assert!((straight.count - reset.count).abs() <= 1, "{} and {}", straight.count, reset.count);
    }

    fn client(path: &str) -> std::fs::File {
        use std::os::unix::fs::OpenOptionsExt;
        std::fs::OpenOptions::new().read(true).write(true).custom_flags(libc::O_NONBLOCK).open(path).unwrap()
    }

    /// What a client reads, once `at_least` bytes came (a pty passes bytes on
    /// through the kernel's buffer a moment later), or after a second.
    fn read_some(term: &mut std::fs::File, at_least: usize) -> Vec<u8> {
        let mut got = Vec::new();
        let mut buf = [0u8; 256];
        for _ in 0..200 {
            while let Ok(n @ 1..) = term.read(&mut buf) {
                got.extend_from_slice(&buf[..n]);
            }
            if got.len() >= at_least {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        got
    }

    #[test]
    fn a_new_client_sees_none_of_the_old_ones_lines() {
        let (mut pty, path) = super::open().expect("openpty");
        let a = client(&path);
        // the old client's reply, never read, and a line after it left
        pty.deliver(b"#71 ok cpr=2400\r\n");
        drop(a);
        pty.deliver(b"ok state=idle\r\n");
        let mut b = client(&path);
        pty.deliver(b"#72 ok edges=3\r\n");
        // the old lines would come first
        assert_eq!(String::from_utf8(read_some(&mut b, 16)).unwrap(), "#72 ok edges=3\r\n");
    }

    #[test]
    fn what_the_host_wrote_before_a_reset_is_dropped() {
        let (pty, path) = super::open().expect("openpty");
        let mut term = client(&path);
        term.write_all(b"#61 set edges 5\r\n#62 save\r\n").unwrap();
        let mut dropped = 0;
        for _ in 0..200 {
            dropped += pty.drop_input();
            if dropped >= 27 {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert_eq!(dropped, 27);
        let mut buf = [0u8; 64];
        assert_eq!(pty.read(&mut buf), 0, "nothing left for the rebooted board");
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
