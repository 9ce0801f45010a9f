//! E-stop (normally closed to GND: open = stop), drive alarm (pulled to GND
//! on alarm) and the lathe index, on EXTI. E-stop and alarm halt the step
//! timer in their own interrupt, at once; the tick then latches the fault.

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use embassy_stm32::gpio::{Input, Pull};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::pac;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;

const INDEX: usize = 0;
const ESTOP: usize = 14;
const ALARM: usize = 15;
const LATCHED: u32 = 1 << 16;
static INDEX_RAW: AtomicU32 = AtomicU32::new(0);
/// Set when this interrupt halted the step output; the tick re-arms it.
static HALTED: AtomicBool = AtomicBool::new(false);

/// True once after the E-stop or alarm interrupt halted the step output.
pub fn take_halted() -> bool {
    HALTED.swap(false, Ordering::Relaxed)
}

pub fn inputs(index: Peri<'static, P::PB0>, estop: Peri<'static, P::PB14>, alarm: Peri<'static, P::PB15>) {
    core::mem::forget(Input::new(index, Pull::Down));
    core::mem::forget(Input::new(estop, Pull::Up));
    core::mem::forget(Input::new(alarm, Pull::Up));
    pac::RCC.apb2enr().modify(|w| w.set_syscfgen(true));
    for line in [INDEX, ESTOP, ALARM] {
        // port B = 1 in SYSCFG_EXTICRx
        pac::SYSCFG.exticr(line / 4).modify(|w| w.set_exti(line % 4, 1));
    }
    pac::EXTI.rtsr(0).modify(|w| {
        w.set_line(INDEX, true);
        w.set_line(ESTOP, true);
    });
    pac::EXTI.ftsr(0).modify(|w| w.set_line(ALARM, true));
    pac::EXTI.imr(0).modify(|w| {
        for line in [INDEX, ESTOP, ALARM] {
            w.set_line(line, true);
        }
    });
    // (their priorities: `board::PRIORITIES`, applied before this)
    // SAFETY: handlers below only touch atomics and the step timer.
    unsafe {
        interrupt::EXTI0.enable();
        interrupt::EXTI15_10.enable();
    }
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

/// The lathe counter latched at the last index pulse, once.
pub fn take_index() -> Option<u16> {
    let v = INDEX_RAW.swap(0, Ordering::Relaxed);
    (v & LATCHED != 0).then_some(v as u16)
}

#[interrupt]
fn EXTI0() {
    let raw = pac::TIM3.cnt().read().cnt();
    pac::EXTI.pr(0).write(|w| w.set_line(INDEX, true));
    INDEX_RAW.store(LATCHED | raw as u32, Ordering::Relaxed);
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
