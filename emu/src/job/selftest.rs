//! Scenario (e): the bench self-test with its jumpers modelled, PA2-PA6, PA3-PA7
//! (TIM9's quadrature into TIM3) and PA4-PB0 (the index), started on the console
//! as a machinist starts it (`selftest start`). It must pass; without the index
//! jumper it must fail naming it.

use super::{ESTOP, GPIOB, MS};
use crate::checks::Report;
use crate::chip::Jumpers;
use crate::image::Image;
use crate::machine::Machine;
use crate::usb::scenario::{enumerate_on, exchange};
use polyturn_stm32_model::Params;
use std::rc::Rc;
use std::time::Instant;

/// Emulated time allowed for the test (it announces about 11 s at its defaults).
const LIMIT_MS: u64 = 30_000;

fn one(image: &Rc<Image>, jumpers: Jumpers) -> Result<(String, String, u64, f64), String> {
    let wall = Instant::now();
    let mut m = Machine::new(image.clone(), Params::default(), &[])?;
    m.chip().jumpers = jumpers;
    m.drive(GPIOB, ESTOP, Some(false));
    let mut m = enumerate_on(m)?.0;
    let started = exchange(&mut m, "selftest start\n")?.0;
    let t0 = m.chip().now;
    let mut last = String::new();
    while m.chip().now - t0 < LIMIT_MS * MS {
        m.run(500 * MS);
        last = exchange(&mut m, "selftest\n")?.0;
        if !last.starts_with("ok selftest running") {
            break;
        }
    }
    Ok((started, last, m.chip().now, wall.elapsed().as_secs_f64()))
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let (started, verdict, t1, wall1) = one(image, Jumpers { ab: true, index: true })?;
    let ok = started.starts_with("ok selftest started") && verdict.starts_with("ok selftest pass ");
    r.line(
        ok,
        "selftest",
        &format!("{started:?} -> {verdict:?} ({:.1} s emulated, {wall1:.1} s wall)", t1 as f64 / 96e6),
    );
    let (_, verdict, t2, wall2) = one(image, Jumpers { ab: true, index: false })?;
    let ok = verdict.starts_with("ok selftest fail") && verdict.contains("jumper PA4 to PB0");
    r.line(
        ok,
        "selftest-no-index",
        &format!("without PA4-PB0: {verdict:?} ({:.1} s emulated, {wall2:.1} s wall)", t2 as f64 / 96e6),
    );
    Ok(t1 + t2)
}
