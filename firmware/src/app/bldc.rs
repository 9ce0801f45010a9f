//! The BLDC drive's output (`polyturn_firmware::bldcout`): TIM10_CH1 on
//! PB8, the sense on BLDC_DIR (PB1). The register words are host-tested
//! data, applied verbatim; the stop's CCR1 and the order of the tick's
//! command against a stop are kept in a `bldcout::Interlock` (host-tested),
//! where the E-stop interrupt and the panic handler reach them without the
//! settings.

use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::pac;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;
use polyturn_firmware::bldcout::{Interlock, Out};
use polyturn_sync::{Config, Controller, Sense};

/// Until `set_up` TIM10 is not clocked and a stop's words do nothing.
static INTERLOCK: Interlock = Interlock::new();
const DIR_PIN: usize = 1;

/// TIM10 clocked, PB8 on it (AF3: PB8 also maps to TIM4, the cutter's
/// encoder, so the AF is set by hand), PB1 an output, low: the saved
/// interface's stop after one frame with no pulse (a PWM driver must never
/// see an RC pulse's 5 % duty), its scale set by the tick's start.
pub fn init(tim: Peri<'static, P::TIM10>, pin: Peri<'static, P::PB8>, dir: Peri<'static, P::PB1>, config: &Config) {
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(tim));
    let _ = pin;
    // the AF before the mode: PB8 never passes through another AF's output
    pac::GPIOB.afr(1).modify(|w| w.set_afr(0, 3));
    pac::GPIOB.moder().modify(|w| w.set_moder(8, pac::gpio::vals::Moder::ALTERNATE));
    core::mem::forget(Output::new(dir, Level::Low, Speed::Low));
    set_up(&Out::new(config, 1));
}

/// The interface the core's settings ask for, scaled to its full speed.
pub fn out_for(core: &Controller) -> Out {
    Out::new(core.config(), core.derived().limits.max_velocity)
}

/// (Re)programs TIM10 for `out` (`Interlock::set_up`).
pub fn set_up(out: &Out) {
    INTERLOCK.set_up(out, &mut super::mmio::Mmio);
}

/// BLDC_DIR: low when the cutter turns the way the core counts up (`dir
/// same`), high the other way.
pub fn set_sense(c: &Config) {
    let high = c.sense == Sense::Opposite;
    pac::GPIOB.bsrr().write(|w| if high { w.set_bs(DIR_PIN, true) } else { w.set_br(DIR_PIN, true) });
}

/// Stops so far, read at the tick's entry for `command`.
#[inline]
pub fn stops() -> u32 {
    INTERLOCK.stops()
}

/// The tick's command, `ccr`, into the preload (`Interlock::command`: not
/// written if a stop came since the tick began, the stop written again if
/// one lands around its word).
#[inline]
pub fn command(ccr: u32, since: u32) {
    INTERLOCK.command(ccr, since, &mut super::mmio::Mmio);
}

/// The tick's halt (an immediate fault): `Interlock::halt`.
#[inline]
pub fn halt() {
    INTERLOCK.halt(&mut super::mmio::Mmio);
}

/// The stop at once, from any context (E-stop, alarm, fault, panic):
/// `bldcout::stop_ops`.
pub fn stop() {
    INTERLOCK.stop(&mut super::mmio::Mmio);
}
