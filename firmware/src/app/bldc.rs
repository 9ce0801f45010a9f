//! The BLDC drive's output (`polyturn_firmware::bldcout`): TIM10_CH1 on
//! PB8, the sense on BLDC_DIR (PB1). The register words are host-tested
//! data, applied verbatim; the stop's CCR1 is kept where the E-stop
//! interrupt and the panic handler can write it without the settings.

use core::sync::atomic::{AtomicU32, Ordering};
use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::pac;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;
use polyturn_firmware::bldcout::Out;
use polyturn_firmware::regs::apply;
use polyturn_sync::{Config, Controller, Sense};

/// CCR1 of the interface's stop (the ESC's 1 000 µs until set up: its
/// value at 1 MHz counts, the first interface's).
static STOP: AtomicU32 = AtomicU32::new(1_000);
const DIR_PIN: usize = 1;

/// TIM10 clocked, PB8 on it (AF3: PB8 also maps to TIM4, the cutter's
/// encoder, so the AF is set by hand), PB1 an output, low: the ESC's
/// stop at 50 Hz until the tick's start sets up the saved interface.
pub fn init(tim: Peri<'static, P::TIM10>, pin: Peri<'static, P::PB8>, dir: Peri<'static, P::PB1>) {
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(tim));
    let _ = pin;
    pac::GPIOB.moder().modify(|w| w.set_moder(8, pac::gpio::vals::Moder::ALTERNATE));
    pac::GPIOB.afr(1).modify(|w| w.set_afr(0, 3));
    core::mem::forget(Output::new(dir, Level::Low, Speed::Low));
    set_up(&Out::new(&Config::default(), 1));
}

/// The interface the core's settings ask for, scaled to its full speed.
pub fn out_for(core: &Controller) -> Out {
    Out::new(core.config(), core.derived().limits.max_velocity)
}

/// (Re)programs TIM10 for `out`: the stop first, so no frame between runs
/// the old interface's pulse on the new frame.
pub fn set_up(out: &Out) {
    STOP.store(out.stop, Ordering::Relaxed);
    let _ = apply(&out.program(), &mut super::drivers::Mmio);
}

/// BLDC_DIR: low when the cutter turns the way the core counts up (`dir
/// same`), high the other way.
pub fn set_sense(c: &Config) {
    let high = c.sense == Sense::Opposite;
    pac::GPIOB.bsrr().write(|w| if high { w.set_bs(DIR_PIN, true) } else { w.set_br(DIR_PIN, true) });
}

#[inline]
pub fn set_ccr(v: u32) {
    pac::TIM10.ccr(0).write(|w| w.set_ccr(v as u16));
}

/// The stop, from any context (E-stop, alarm, panic).
pub fn stop() {
    set_ccr(STOP.load(Ordering::Relaxed));
}
