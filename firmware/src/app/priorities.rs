//! Applies `board::PRIORITIES` and checks, at boot, that no enabled
//! interrupt reaches the tick's step plan's level but the plan, the tick
//! and the E-stop above them
//! (an interrupt enabled by a driver without a priority is at 0, the
//! E-stop's, above the tick).

use cortex_m::interrupt::InterruptNumber;
use cortex_m::peripheral::NVIC;
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::{InterruptExt, Priority};
use polyturn_firmware::board::{ESTOP_IRQ, PRIORITIES};

fn level(n: u8) -> Priority {
    // the NVIC keeps the top 4 bits (RM0383 / PM0214 §4.3.7)
    Priority::from(n << 4)
}

pub fn apply() {
    for &(name, n) in PRIORITIES {
        let p = level(n);
        match name {
            "TIM1_TRG_COM_TIM11" => interrupt::TIM1_TRG_COM_TIM11.set_priority(p),
            "EXTI15_10" => interrupt::EXTI15_10.set_priority(p),
            "TIM5" => interrupt::TIM5.set_priority(p),
            "TIM1_BRK_TIM9" => interrupt::TIM1_BRK_TIM9.set_priority(p),
            "OTG_FS" => interrupt::OTG_FS.set_priority(p),
            "USART6" => interrupt::USART6.set_priority(p),
            "USART2" => interrupt::USART2.set_priority(p),
            _ => defmt::error!("priority map: unknown interrupt {}", name),
        }
    }
}

#[derive(Clone, Copy)]
struct Irq(u16);
// SAFETY: any number below the F411's 86 vectors is a valid interrupt.
unsafe impl InterruptNumber for Irq {
    fn number(self) -> u16 {
        self.0
    }
}

/// True when every enabled interrupt at or above the step plan's level is
/// the tick, its plan or the E-stop, the E-stop is above the tick, the
/// plan below it, and all 4 priority
/// bits are group priority
/// (AIRCR.PRIGROUP ≤ 3, PM0214 §4.4.5: `cs.rs`'s BASEPRI mask assumes it);
/// logs each that is not.
pub fn check() -> bool {
    let tick = interrupt::TIM1_TRG_COM_TIM11.get_priority();
    let plan = interrupt::USART2.get_priority();
    let allowed = [interrupt::TIM1_TRG_COM_TIM11.number(), interrupt::USART2.number(), estop()];
    // SAFETY: a read of SCB.AIRCR
    let prigroup = (unsafe { (*cortex_m::peripheral::SCB::PTR).aircr.read() } >> 8) & 7;
    let mut ok = prigroup <= 3;
    if !ok {
        defmt::error!("AIRCR.PRIGROUP is {}: priority levels split", prigroup);
    }
    if NVIC::get_priority(Irq(estop())) >= u8::from(tick) {
        defmt::error!("the E-stop does not pre-empt the tick");
        ok = false;
    }
    if u8::from(plan) <= u8::from(tick) {
        defmt::error!("the tick does not pre-empt its step plan");
        ok = false;
    }
    for n in 0..86u16 {
        let irq = Irq(n);
        if NVIC::is_enabled(irq) && NVIC::get_priority(irq) <= u8::from(plan) && !allowed.contains(&n) {
            defmt::error!("interrupt {} is enabled at the tick's or its plan's priority", n);
            ok = false;
        }
    }
    ok
}

fn estop() -> u16 {
    match ESTOP_IRQ {
        "EXTI15_10" => interrupt::EXTI15_10.number(),
        _ => u16::MAX,
    }
}
