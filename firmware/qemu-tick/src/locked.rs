//! The firmware's sections that hold off the tick: every closure the
//! firmware runs under the tick's lock (`tick::with_core` from the console,
//! the service task, the report, the LED loop), measured on the same core
//! code. Each is the closure alone; the lock (`tick::locked`: BASEPRI
//! raised and restored) and the RefCell borrow add about 12 instructions
//! around it. The E-stop, above the tick, is not held off by them.

use crate::meter::{measure, TIMING};
use core::sync::atomic::{AtomicBool, Ordering};
use cortex_m::peripheral::SYST;
use cortex_m_semihosting::hprintln;
use polyturn_sync::cam_upload::CamHeader;
use polyturn_sync::console::{self, Snapshot};
use polyturn_sync::controller::prepare_cam;
use polyturn_sync::{Config, Controller, TickInput};

/// Set if a measured command was refused: its figure would not be the
/// work it does when it succeeds.
static REFUSED: AtomicBool = AtomicBool::new(false);

fn refused_if(bad: bool) {
    if bad {
        REFUSED.store(true, Ordering::Relaxed);
    }
}

static CAM: [i32; 64] = {
    let mut t = [0i32; 64];
    let mut i = 0;
    while i < 64 {
        t[i] = (i as i32 % 8) * 40;
        i += 1;
    }
    t
};

/// Runs `f` on `c` `n` times (state restored by `setup` each time) and
/// returns the worst cost in instructions.
fn worst(syst: &SYST, per_1201: u32, setup: &dyn Fn() -> Controller, f: &dyn Fn(&mut Controller)) -> u32 {
    let mut w = 0;
    for _ in 0..8 {
        let mut c = setup();
        w = w.max(measure(syst, || f(&mut c)));
    }
    (w as u64 * 1201 / per_1201 as u64) as u32
}

fn idle() -> Controller {
    let mut c = Controller::new(Config::default(), TIMING);
    c.start(0, 0, 0);
    c.tick(&TickInput::default());
    c
}

fn engaged() -> Controller {
    let mut c = idle();
    let _ = c.engage();
    c.tick(&TickInput::default());
    c
}

/// Idle with the lathe known to be at rest (the estimator's still time).
fn rested() -> Controller {
    let mut c = idle();
    for _ in 0..TIMING.tick_hz / 10 + 10 {
        c.tick(&TickInput::default());
    }
    c
}

/// A self-test just started (`selftest start`).
fn selftesting() -> Controller {
    let mut c = rested();
    refused_if(c.start_selftest(None).is_err());
    c.tick(&TickInput::default());
    c
}

/// A save's stall during which the lathe turned too far to count.
fn stalled() -> Controller {
    let mut c = idle();
    c.begin_stall();
    c.tick(&TickInput { lathe: 30_000, ..TickInput::default() });
    c
}

/// A console line prepared outside the lock from the settings of `from`'s
/// controller (as the firmware prepares it), applied under it.
fn set(line: &'static [u8], from: fn() -> Controller) -> impl Fn(&mut Controller) {
    let cmd = console::parse(line);
    let c = from();
    let pre = console::prepare(&cmd, *c.config(), c.config_generation(), TIMING);
    move |c: &mut Controller| {
        let o = console::apply_prepared(cmd, pre, c);
        refused_if(matches!(
            o,
            console::Outcome::Error(_) | console::Outcome::FieldError(..) | console::Outcome::SelfTestRefused(_)
        ));
    }
}

/// A console line with nothing to prepare.
fn cmd(line: &'static [u8]) -> impl Fn(&mut Controller) {
    let cmd = console::parse(line);
    move |c: &mut Controller| {
        let o = console::apply_prepared(cmd, None, c);
        refused_if(matches!(
            o,
            console::Outcome::Error(_) | console::Outcome::FieldError(..) | console::Outcome::SelfTestRefused(_)
        ));
    }
}

/// The judge's verdict that ends a test (the generator stopped early),
/// judged outside the lock as the firmware does.
fn ended() -> Option<polyturn_sync::controller::selftest::Pending> {
    let c = selftesting();
    let mut p = c.selftest_pending();
    if let Some(p) = &mut p {
        p.judge(&polyturn_sync::selftest::Books::default());
    }
    p
}

/// Prints each section and the longest; `None` if a measured command was
/// refused (then the figures are not what they claim).
pub fn report(syst: &SYST, per_1201: u32) -> Option<u32> {
    let head =
        CamHeader { points: 64, period_counts: 2400, counts_per_rev: 2400, max_rate_hz: 10_000, max_accel: 2_000_000 };
    let x = prepare_cam(&head, &CAM, TIMING).ok();
    let nudge = set(b"set phase 12.5", engaged);
    let ratio = set(b"set ratio 3/2", idle);
    let defaults = set(b"defaults", idle);
    let selftest_start = set(b"selftest start", rested);
    let ended = ended();
    refused_if(ended.is_none());
    let sections: [(&str, &dyn Fn() -> Controller, &dyn Fn(&mut Controller)); 15] = [
        ("copy of the settings", &idle, &|c| {
            core::hint::black_box(*c.config());
        }),
        ("set phase while engaged (nudge)", &engaged, &nudge),
        ("set ratio while idle", &idle, &ratio),
        ("defaults", &idle, &defaults),
        ("engage", &idle, &cmd(b"engage")),
        ("stop", &engaged, &cmd(b"stop")),
        ("status / report / watch snapshot", &engaged, &|c| {
            core::hint::black_box(Snapshot::of(c));
        }),
        ("service task (service + state)", &engaged, &|c| {
            c.service();
            core::hint::black_box(c.state());
        }),
        ("install a prepared cam", &idle, &|c| {
            let r = x.as_ref().map(|x| c.install_cam(&head, x.clone()));
            refused_if(!matches!(r, Some(Ok(()))));
        }),
        ("begin a save's stall", &idle, &|c| c.begin_stall()),
        ("end a save's stall (lathe lost: re-base)", &stalled, &|c| {
            core::hint::black_box(c.end_stall());
        }),
        ("selftest start (planned outside)", &rested, &selftest_start),
        ("self-test: the judge's copy (every ms)", &selftesting, &|c| {
            core::hint::black_box(c.selftest_pending());
        }),
        ("self-test: keep the verdict and end it", &selftesting, &|c| {
            if let Some(p) = ended {
                c.selftest_judged(p);
            }
        }),
        ("LED loop (state)", &engaged, &|c| {
            core::hint::black_box(c.state());
        }),
    ];
    let mut longest = (0, "");
    for (name, setup, f) in sections {
        let n = worst(syst, per_1201, setup, f);
        hprintln!("locked section: {} instructions: {}", n, name);
        if n > longest.0 {
            longest = (n, name);
        }
    }
    hprintln!("longest locked section: {} instructions ({}), plus ~12 for the lock itself", longest.0, longest.1);
    if REFUSED.load(Ordering::Relaxed) {
        hprintln!("error: a measured command was refused");
        return None;
    }
    Some(longest.0)
}
