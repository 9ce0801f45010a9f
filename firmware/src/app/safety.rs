//! E-stop (normally closed to GND: open = stop) and drive alarm (pulled to
//! GND on alarm), on EXTI. They halt the step output and stop the ESC in
//! their own interrupt, at once; the tick then latches the fault. (The
//! lathe index is latched by TIM3 in hardware: `drivers::take_index`.)

use core::sync::atomic::{AtomicBool, Ordering};
use embassy_stm32::gpio::{Input, Pull};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::pac;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;

const ESTOP: usize = 14;
const ALARM: usize = 15;
/// Set when this interrupt halted the step output; the tick re-arms it.
static HALTED: AtomicBool = AtomicBool::new(false);

/// True once after the E-stop or alarm interrupt halted the step output.
pub fn take_halted() -> bool {
    HALTED.swap(false, Ordering::Relaxed)
}

pub fn inputs(estop: Peri<'static, P::PB14>, alarm: Peri<'static, P::PB15>) {
    core::mem::forget(Input::new(estop, Pull::Up));
    core::mem::forget(Input::new(alarm, Pull::Up));
    pac::RCC.apb2enr().modify(|w| w.set_syscfgen(true));
    for line in [ESTOP, ALARM] {
        // port B = 1 in SYSCFG_EXTICRx
        pac::SYSCFG.exticr(line / 4).modify(|w| w.set_exti(line % 4, 1));
    }
    pac::EXTI.rtsr(0).modify(|w| w.set_line(ESTOP, true));
    pac::EXTI.ftsr(0).modify(|w| w.set_line(ALARM, true));
    pac::EXTI.imr(0).modify(|w| {
        for line in [ESTOP, ALARM] {
            w.set_line(line, true);
        }
    });
    // (their priorities: `board::PRIORITIES`, applied before this)
    // SAFETY: the handler below only touches an atomic and the outputs.
    unsafe { interrupt::EXTI15_10.enable() };
}

fn pin_high(n: usize) -> bool {
    pac::GPIOB.idr().read().idr(n) == pac::gpio::vals::Idr::HIGH
}

pub fn estop_open() -> bool {
    pin_high(ESTOP)
}

pub fn alarm() -> bool {
    !pin_high(ALARM)
}

#[interrupt]
fn EXTI15_10() {
    pac::EXTI.pr(0).write(|w| {
        w.set_line(ESTOP, true);
        w.set_line(ALARM, true);
    });
    if estop_open() || alarm() {
        super::drivers::halt_steps();
        super::drivers::set_esc_pulse_us(polyturn_firmware::esc::STOP_US);
        HALTED.store(true, Ordering::Relaxed);
    }
}
