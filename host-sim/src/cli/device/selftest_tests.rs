//! `polyturn device selftest` against the real console, on a fake board
//! whose machine plays the firmware's own generator into the lathe input
//! as the app does (`Workshop`).

use super::checks::selftest;
use super::tests::{session, FakeDevice};
use polyturn_bench::fakeboard::{ticks_in_ms, Workshop};

/// A board whose lathe input turns at `counts_per_s` (0: at rest), 1 s of
/// it passing between lines.
fn board(counts_per_s: u32) -> super::session::Session<FakeDevice> {
    let mut dev = FakeDevice::new();
    let mut m = Workshop::new(ticks_in_ms(1_000));
    m.turn_at(counts_per_s);
    dev.workshop = Some(m);
    session(dev)
}

#[test]
fn a_good_board_passes_and_the_host_shows_the_figures() {
    let mut s = board(0);
    let out = selftest(&mut s, "selftest start 300").unwrap();
    let mut lines = out.lines();
    assert!(lines.next().unwrap().starts_with("ok selftest started rpm=300 cpr=2400 seconds=11.2"), "{out}");
    let pass = lines.next().unwrap();
    assert!(pass.starts_with("ok selftest pass rpm=300 forward="), "{pass}");
    // 2 s at 300 rpm: 24 000 counts, 64 000 steps (8/3 a count)
    assert!(pass.contains("hold_steps=6400"), "{pass}");
    // it asked for the figures until the end, not once
    let polls = s.io.received.iter().filter(|l| l.ends_with(" selftest")).count();
    assert!((11..=14).contains(&polls), "{polls} polls");
}

#[test]
fn a_refusal_or_a_failure_is_an_error_with_the_boards_reason() {
    let mut s = board(0);
    let e = selftest(&mut s, "selftest start 900").unwrap_err();
    assert!(e.0.contains("selftest start rpm: 1..=319"), "{}", e.0);
    // a lathe turning under the test: refused before it starts
    let mut s = board(10_000);
    let e = selftest(&mut s, "selftest start").unwrap_err();
    assert!(e.0.contains("the lathe input is moving"), "{}", e.0);
    // an E-stop midway: a failure naming it (here the first line only
    // reads the figures: the test was started and tripped before)
    let mut s = board(0);
    s.ask("selftest start").unwrap();
    s.io.ctl.trip(polyturn_sync::Fault::EStop);
    let e = selftest(&mut s, "selftest").unwrap_err();
    assert!(e.0.starts_with("device: the self-test failed: fault estop: e-stop open"), "{}", e.0);
}

/// A port that answers each command, tagged, with the next of `script`.
pub(super) struct Replier {
    pub script: std::collections::VecDeque<&'static str>,
    out: Vec<u8>,
}

impl Replier {
    pub fn new(script: &[&'static str]) -> Replier {
        Replier { script: script.iter().copied().collect(), out: vec![] }
    }
}

impl std::io::Read for Replier {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.out.is_empty() {
            return Err(std::io::ErrorKind::TimedOut.into());
        }
        let n = buf.len().min(self.out.len());
        buf[..n].copy_from_slice(&self.out[..n]);
        self.out.drain(..n);
        Ok(n)
    }
}

impl std::io::Write for Replier {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        let line = String::from_utf8_lossy(data);
        let tag = line.split(' ').next().unwrap_or("");
        if let Some(answer) = self.script.pop_front() {
            self.out.extend(format!("{tag} {answer}\r\n").as_bytes());
        }
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn a_self_test_length_no_board_would_plan_is_no_panic_and_no_endless_wait() {
    for seconds in ["1e308", "inf", "-1", "NaN"] {
        let started: &'static str = Box::leak(format!("ok selftest started rpm=1 cpr=4 seconds={seconds}:").into());
        let mut s = session(Replier::new(&[started, "ok selftest pass rpm=1"]));
        assert!(selftest(&mut s, "selftest start").unwrap().ends_with("ok selftest pass rpm=1"), "{seconds}");
    }
}
