//! E-stop (normally closed to GND: open = stop) and drive alarm (pulled to
//! GND on alarm), on EXTI. They halt the step output and stop the ESC in
//! their own interrupt, at once: it is the most urgent (`board::PRIORITIES`),
//! so it pre-empts even the tick, and the tick re-applies the stop if it
//! ran inside it; the tick then latches the fault. (The
//! lathe index is latched by TIM3 in hardware: `drivers::index`.)

use core::sync::atomic::{AtomicU32, AtomicU8, Ordering};
use embassy_stm32::gpio::{Input, Pull};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::pac;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;

const ESTOP: usize = 14;
const ALARM: usize = 15;
/// How many times this interrupt has stopped the outputs (the tick compares
/// it with what it saw before, to re-arm, and across its own run, to re-stop).
static HALTS: AtomicU32 = AtomicU32::new(0);

pub fn halts() -> u32 {
    HALTS.load(Ordering::Relaxed)
}

/// What this interrupt saw when it stopped the outputs, until the tick takes
/// it: bit 0 the E-stop open, bit 1 the drive's alarm. A contact that opened
/// and closed again between two ticks still stopped the cutter, so the tick
/// latches it as the fault it was (and the books take the halted count).
static FIRED: AtomicU8 = AtomicU8::new(0);
const FIRED_ESTOP: u8 = 1;
const FIRED_ALARM: u8 = 2;

/// (E-stop, alarm): each true if it fired this interrupt since the last call.
pub fn take_fired() -> (bool, bool) {
    let f = FIRED.swap(0, Ordering::Relaxed);
    (f & FIRED_ESTOP != 0, f & FIRED_ALARM != 0)
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

/// Only the stopping edges are enabled on these lines (RTSR for the E-stop
/// opening, FTSR for the alarm), so every entry is a stop: TIM1 stops
/// first, before anything is read. Which line fired comes from the pending
/// bits, not the pin levels (a bouncing contact may read closed again by
/// now: EXTI_PR latches the edge, RM0383 §10.2, §10.3.6); only the bits read are
/// cleared, so an edge arriving meanwhile pends again.
#[interrupt]
fn EXTI15_10() {
    super::drivers::stop_step_timer();
    let pr = pac::EXTI.pr(0).read();
    let (estop, alarm) = (pr.line(ESTOP), pr.line(ALARM));
    pac::EXTI.pr(0).write(|w| {
        w.set_line(ESTOP, estop);
        w.set_line(ALARM, alarm);
    });
    // (TIM1's counter again, with the rest: one write)
    super::drivers::stop_actuators();
    HALTS.fetch_add(1, Ordering::Relaxed);
    FIRED.fetch_or((estop as u8 * FIRED_ESTOP) | (alarm as u8 * FIRED_ALARM), Ordering::Relaxed);
}
