//! The BLDC drive's output (`polyturn_firmware::bldcout`): TIM10_CH1 on
//! PB8, the sense on BLDC_DIR (PB1). The register words are host-tested
//! data, applied verbatim; the stop's CCR1 is kept where the E-stop
//! interrupt and the panic handler can write it without the settings.

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::pac;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;
use polyturn_firmware::bldcout::{run_ops, stop_ops, Out};
use polyturn_firmware::regs::apply;
use polyturn_sync::{Config, Controller, Sense};

/// CCR1 of the interface's stop, kept by `set_up` (until then TIM10 is not
/// clocked and a write does nothing).
static STOP: AtomicU32 = AtomicU32::new(0);
/// Cleared by every stop: the tick's command sees whether one came
/// between its words.
static LIVE: AtomicBool = AtomicBool::new(false);
const DIR_PIN: usize = 1;

/// TIM10 clocked, PB8 on it (AF3: PB8 also maps to TIM4, the cutter's
/// encoder, so the AF is set by hand), PB1 an output, low: the saved
/// interface's stop from its first frame (a PWM driver must never see an
/// RC pulse's 5 % duty), its scale set by the tick's start.
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

/// (Re)programs TIM10 for `out`. Its stop is 0 (no pulse) while the words
/// go in, so an E-stop among them cannot put the new stop in the old frame.
pub fn set_up(out: &Out) {
    STOP.store(0, Ordering::Relaxed);
    LIVE.store(false, Ordering::Relaxed);
    let _ = apply(&out.program(), &mut super::drivers::Mmio);
    STOP.store(out.stop, Ordering::Relaxed);
}

/// BLDC_DIR: low when the cutter turns the way the core counts up (`dir
/// same`), high the other way.
pub fn set_sense(c: &Config) {
    let high = c.sense == Sense::Opposite;
    pac::GPIOB.bsrr().write(|w| if high { w.set_bs(DIR_PIN, true) } else { w.set_br(DIR_PIN, true) });
}

/// The tick's command: `ccr`, or the stop if it is the stop (written when
/// the drive was running: once stopped, every writer of TIM10 leaves the
/// stop in force, so an idle or stepper tick writes nothing). A running
/// command is preloaded (`bldcout::run_ops`). The E-stop may come between
/// its two words: then the second went in with the preload off, so the
/// stop is written again at once (and again at the tick's end).
#[inline]
pub fn command(ccr: u32) {
    if ccr == STOP.load(Ordering::Relaxed) {
        if LIVE.load(Ordering::Relaxed) {
            stop();
        }
        return;
    }
    LIVE.store(true, Ordering::Relaxed);
    let _ = apply(&run_ops(ccr), &mut super::drivers::Mmio);
    if !LIVE.load(Ordering::Relaxed) {
        stop();
    }
}

/// The stop at once, from any context (E-stop, alarm, fault, panic):
/// `bldcout::stop_ops`.
pub fn stop() {
    LIVE.store(false, Ordering::Relaxed);
    let _ = apply(&stop_ops(STOP.load(Ordering::Relaxed)), &mut super::drivers::Mmio);
}
