//! Scenario (e): the bench self-test with its jumpers modelled, PA2-PA6, PA3-PA7
//! (TIM9's quadrature into TIM3) and PA4-PB0 (the index), started on the console
//! as a machinist starts it (`selftest start`), and at the generator's top speed
//! as the bench procedure runs it. Each must pass, its index handler within
//! `quadgen::LATENCY_MAX` on the bound; without the index jumper it must fail
//! naming it.

use super::{ESTOP, GPIOB, MS};
use crate::checks::Report;
use crate::chip::probe::IndexTiming;
use crate::chip::Jumpers;
use crate::image::Image;
use crate::machine::Machine;
use crate::usb::scenario::{enumerate_on, exchange};
use polyturn_stm32_model::Params;
use std::rc::Rc;
use std::time::Instant;

/// Emulated time allowed for the test (it announces about 11 s at its defaults).
const LIMIT_MS: u64 = 30_000;

/// What one run of the test gave: the reply to `selftest start`, the last
/// reply, the MCU's cycles, the wall's seconds, and the index handler's
/// timing.
struct Run {
    started: String,
    verdict: String,
    cycles: u64,
    wall_s: f64,
    index: IndexTiming,
}

fn one(image: &Rc<Image>, jumpers: Jumpers, start: &str) -> Result<Run, String> {
    let wall = Instant::now();
    let mut m = Machine::new(image.clone(), Params::default(), &[])?;
    m.chip().jumpers = jumpers;
    m.chip().probe.index = Some(IndexTiming::default());
    m.drive(GPIOB, ESTOP, Some(false));
    let mut m = enumerate_on(m)?.0;
    let started = exchange(&mut m, start)?.0;
    let t0 = m.chip().now;
    let mut last = String::new();
    while m.chip().now - t0 < LIMIT_MS * MS {
        m.run(500 * MS);
        last = exchange(&mut m, "selftest\n")?.0;
        if !last.starts_with("ok selftest running") {
            break;
        }
    }
    let index = m.chip().probe.index.take().unwrap_or_default();
    Ok(Run { started, verdict: last, cycles: m.chip().now, wall_s: wall.elapsed().as_secs_f64(), index })
}

/// A run with both jumpers must pass, and its index handler answer within
/// `quadgen::LATENCY_MAX` on the bound: the figure the generator's top
/// speed rests on (a later index write latches the wrong count).
fn passes(image: &Rc<Image>, r: &mut Report, name: &str, start: &str) -> Result<u64, String> {
    let run = one(image, Jumpers { ab: true, index: true }, start)?;
    let ok = run.started.starts_with("ok selftest started") && run.verdict.starts_with("ok selftest pass ");
    let line = format!(
        "{:?} -> {:?} ({:.1} s emulated, {:.1} s wall)",
        run.started,
        run.verdict,
        run.cycles as f64 / 96e6,
        run.wall_s
    );
    r.line(ok, name, &line);
    let ix = &run.index;
    let max = polyturn_firmware::quadgen::LATENCY_MAX as u64;
    r.line(
        ix.writes > 0 && ix.untimed == 0 && ix.worst_bound <= max,
        &format!("{name} index latency"),
        &format!(
            "TIM9's update to the index write, worst of {} writes: model {} cycles, bound {}; LATENCY_MAX {max}; {} not timed",
            ix.writes, ix.worst_model, ix.worst_bound, ix.untimed
        ),
    );
    Ok(run.cycles)
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let t1 = passes(image, r, "selftest", "selftest start\n")?;
    // the generator's top speed at the default 2400 counts, as the bench
    // procedure runs it
    let top = polyturn_sync::selftest::generator_max_rpm(2400);
    let t2 = passes(image, r, "selftest-top", &format!("selftest start {top}\n"))?;
    let run = one(image, Jumpers { ab: true, index: false }, "selftest start\n")?;
    let ok = run.verdict.starts_with("ok selftest fail") && run.verdict.contains("jumper PA4 to PB0");
    r.line(
        ok,
        "selftest-no-index",
        &format!(
            "without PA4-PB0: {:?} ({:.1} s emulated, {:.1} s wall)",
            run.verdict,
            run.cycles as f64 / 96e6,
            run.wall_s
        ),
    );
    Ok(t1 + t2 + run.cycles)
}
