//! Scenario (d): settings saved on the console and loaded after a reset. The
//! image boots on the hexagon's settings (saved in flash before boot), the
//! emulated USB host sends `set ratio 5/2` and `save`; the save's sector erase
//! stalls the CPU for the flash model's erase time while the watchdog, reloaded
//! before it, must not run out (its shortest timeout, at the LSI's fastest);
//! then a reset, and `get ratio` must answer 5/2. The erase's lost ticks
//! are the save's: the image's watch on lost ticks must count none.

use super::{scenario, settings, ESTOP, GPIOB, MS};
use crate::checks::Report;
use crate::image::Image;
use crate::machine::Machine;
use crate::usb::scenario::{enumerate_on, exchange, exchange_within};
use polyturn_stm32_model::chip::iwdg::LSI_HZ;
use polyturn_stm32_model::Params;
use std::rc::Rc;

/// A sector erase takes up to 2 s at ×32 (DS10314); the reply comes after it.
const SAVE_LIMIT_MS: u64 = 3_000;

fn booted(m: Machine) -> Result<Machine, String> {
    let mut m = m;
    m.drive(GPIOB, ESTOP, Some(false));
    Ok(enumerate_on(m)?.0)
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let cfg = scenario(&super::super::jobs::SPECS[0]).core; // the hexagon's
    let m = Machine::new(image.clone(), Params::default(), &settings::saved(&cfg)?)?;
    let mut m = booted(m)?;
    let loaded = exchange(&mut m, "get ratio\n")?.0;
    let set = exchange(&mut m, "set ratio 5/2\n")?.0;
    // the controller calls the lathe at rest once it has been still a while
    // (`Controller::lathe_at_rest`); only then is a save taken
    m.run(1_200 * MS);
    let (t0, stall0) = (m.chip().now, m.chip().stalled);
    let (saved, save_ms, _) = exchange_within(&mut m, "save\n", SAVE_LIMIT_MS)?;
    let stalled_ms = (m.chip().stalled - stall0) as f64 / MS as f64;
    let c = m.chip();
    let gap = c.iwdg.longest_gap(t0, c.now);
    let shortest_ms = m.chip().iwdg.timeout_ns(LSI_HZ[2]) as f64 / 1e6;
    // the erase's lost ticks are the save's, known: the watch on ticks
    // that never ran (`edgetime::watch`) stops through it and counts none
    m.run(20 * MS);
    let lost = super::lost::counted(&mut m);
    let total = m.chip().now;
    let mut m = booted(m.reset()?)?;
    let after = exchange(&mut m, "get ratio\n")?.0;
    let ok = loaded == "ok ratio=2"
        && set == "ok ratio=5/2"
        && saved.starts_with("ok saved")
        && after == "ok ratio=5/2"
        && (gap as f64 / MS as f64) < shortest_ms
        && stalled_ms > 0.0
        && lost.seen > 0
        && lost.image == Some(0);
    let text = format!(
        "before: {loaded:?} (from flash), {set:?}, save: {saved:?} after {save_ms:.0} ms emulated ({stalled_ms:.0} ms of it the CPU stalled by flash), longest watchdog gap {:.0} ms (shortest timeout {shortest_ms:.0} ms), {} TIM11 updates unanswered through it and the image's watch counted {:?} lost; after a reset: {after:?}",
        gap as f64 / MS as f64,
        lost.seen,
        lost.image
    );
    r.line(ok, "save-reset", &text);
    Ok(total + m.chip().now)
}
