//! A long simulation shows that it is alive: 600 s of lathe time at 20 kHz
//! is 12 million ticks, some seconds of work with nothing to see. On a
//! terminal, stderr gets one line, rewritten each second, and cleared at
//! the end; piped or redirected, nothing (a log gets no carriage returns).

use crate::sim::{run, Scenario, SimResult};
use std::io::Write;
use std::time::Duration;

/// Quiet for this long first: a short run shows nothing at all.
const EVERY: Duration = Duration::from_secs(1);

/// Runs `sc`, with a sign of life on stderr when it is a terminal.
pub fn run_alive(sc: &Scenario, turns: f64, rpm: f64) -> Result<SimResult, String> {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return run(sc);
    }
    let (done, finished) = std::sync::mpsc::channel();
    std::thread::scope(|s| {
        let worker = s.spawn(move || {
            let r = run(sc);
            let _ = done.send(());
            r
        });
        let mut waited = 0;
        while finished.recv_timeout(EVERY).is_err() && !worker.is_finished() {
            waited += 1;
            let _ = write!(std::io::stderr().lock(), "\r{}", line(turns, rpm, waited));
        }
        if waited > 0 {
            // erase the line, so the report starts on a clean one
            let _ = write!(std::io::stderr().lock(), "\r\x1b[K");
        }
        worker.join().unwrap_or_else(|_| Err("the simulation stopped unexpectedly".into()))
    })
}

/// What the line says after `seconds` of waiting.
fn line(turns: f64, rpm: f64, seconds: u32) -> String {
    format!(
        "simulating {turns} lathe turns at {rpm} rpm ({:.0} s of cutting, tick by tick): {seconds} s so far",
        turns * 60.0 / rpm
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sign_of_life_says_what_runs_and_for_how_long_on_one_line() {
        let l = line(600.0, 60.0, 7);
        assert_eq!(l, "simulating 600 lathe turns at 60 rpm (600 s of cutting, tick by tick): 7 s so far");
        assert!(!l.contains('\n'));
    }
}
