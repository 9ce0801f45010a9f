//! The MCU application: wires the Black Pill's hardware to the sync core.
//! Priorities (`board::PRIORITIES`, applied and checked at boot): the
//! E-stop highest, the control tick (TIM11 update) next, then the tick's
//! step plan (USART2's vector); then the self-test's generator, embassy's
//! timer, USB; the planning executor (InterruptExecutor on USART6's vector)
//! below them; console, flash, logging and the watchdog in the thread
//! executor.

mod bldc;
mod cs;
mod dfu;
mod drivers;
mod heartbeat;
mod keys;
mod mmio;
mod priorities;
mod ramcode;
mod report;
mod safety;
mod seal;
mod selftest;
mod service;
mod settings;
mod tick;
mod usb;

use defmt::{info, warn};
use defmt_rtt as _;
use embassy_executor::{InterruptExecutor, Spawner};
use embassy_stm32::interrupt;
use embassy_stm32::time::Hertz;
use embassy_stm32::wdg::IndependentWatchdog;
use polyturn_firmware::board;

/// A panic stops the cutter at once (no steps, ENABLE inactive), logs, and
/// traps so a probe shows the backtrace; the watchdog then resets the MCU.
/// Interrupts go off first: the tick (above the logger's critical section,
/// `cs.rs`) would otherwise turn ENABLE and the ESC back on meanwhile. A
/// panic inside the log (defmt) only traps.
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    use core::sync::atomic::{AtomicBool, Ordering};
    static PANICKING: AtomicBool = AtomicBool::new(false);
    cortex_m::interrupt::disable();
    // (the outputs' code runs from SRAM: before it is there, nothing drives
    // them yet)
    if ramcode::mapped() {
        drivers::all_outputs_off();
    }
    if !PANICKING.swap(true, Ordering::Relaxed) {
        defmt::error!("panic: outputs off, waiting for the watchdog reset");
    }
    cortex_m::asm::udf()
}

/// A fault, or an interrupt nothing handles: every output off, interrupts
/// off, then wait for the watchdog (cortex-m-rt's defaults only spin,
/// leaving ENABLE and the ESC as they were, and an unhandled interrupt at
/// the tick's level would starve it).
#[cortex_m_rt::exception]
unsafe fn HardFault(_frame: &cortex_m_rt::ExceptionFrame) -> ! {
    cortex_m::interrupt::disable();
    if ramcode::mapped() {
        drivers::all_outputs_off();
    }
    loop {
        cortex_m::asm::nop();
    }
}

#[cortex_m_rt::exception]
unsafe fn DefaultHandler(_irqn: i16) {
    cortex_m::interrupt::disable();
    if ramcode::mapped() {
        drivers::all_outputs_off();
    }
    loop {
        cortex_m::asm::nop();
    }
}

static PLANNER: InterruptExecutor = InterruptExecutor::new();

/// The image's marker (`polyturn_firmware::dfu::IMAGE_ID`), kept in the
/// image for `polyturn flash` to find.
#[used]
static IMAGE_ID: &str = polyturn_firmware::dfu::IMAGE_ID;

/// The watchdog: `iwdg::WATCHDOG_US` as embassy computes it for a 32 kHz
/// LSI, really 5.4 to 15 s over the F411's LSI range (`iwdg`), longer than
/// a settings save (`flashprog`: the erase pets it first). A hung tick
/// leaves at most two ticks of queued steps, then silent fillers
/// (stepgen); the reset then disables ENABLE.
use polyturn_firmware::iwdg::WATCHDOG_US;

/// Flash prefetch and both caches on: embassy's init sets only the wait
/// states (RM0383 §3.4.1 FLASH_ACR), and without them every figure in
/// cycles is worse than the instruction counts suggest. The data cache is
/// turned off and reset around flash writes (`settings::cache_off`).
fn flash_accelerator_on() {
    embassy_stm32::pac::FLASH.acr().modify(|w| {
        w.set_prften(true);
        w.set_icen(true);
        w.set_dcen(true);
    });
}

#[interrupt]
unsafe fn USART6() {
    // SAFETY: the executor's own interrupt, as embassy-executor documents.
    unsafe { PLANNER.on_interrupt() }
}

/// 25 MHz HSE → 96 MHz system clock, 48 MHz for USB; all timers at 96 MHz.
/// The divisors are `clocks::CLOCKS`'s, whose timer clock the sync core
/// plans with (`Timing::FIRMWARE`): the assertion keeps the two the same.
fn clocks() -> embassy_stm32::Config {
    use embassy_stm32::rcc::*;
    const C: polyturn_firmware::clocks::Clocks = polyturn_firmware::clocks::CLOCKS;
    const _: () = assert!(
        C.hse_hz == 25_000_000
            && C.pll_m == 25
            && C.pll_n == 192
            && C.pll_p == 2
            && C.pll_q == 4
            && C.ahb_div == 1
            && C.apb1_div == 2
            && C.apb2_div == 1,
        "embassy's RCC settings below must be clocks::CLOCKS"
    );
    let mut c = embassy_stm32::Config::default();
    c.rcc.hse = Some(Hse { freq: Hertz(25_000_000), mode: HseMode::Oscillator });
    c.rcc.pll_src = PllSource::HSE;
    c.rcc.pll = Some(Pll {
        prediv: PllPreDiv::DIV25,
        mul: PllMul::MUL192,
        divp: Some(PllPDiv::DIV2),
        divq: Some(PllQDiv::DIV4),
        divr: None,
    });
    c.rcc.sys = Sysclk::PLL1_P;
    c.rcc.ahb_pre = AHBPrescaler::DIV1;
    c.rcc.apb1_pre = APBPrescaler::DIV2;
    c.rcc.apb2_pre = APBPrescaler::DIV1;
    c.rcc.mux.clk48sel = mux::Clk48sel::PLL1_Q;
    // embassy enables all 16 DMA streams' interrupts at this level (0 by
    // default: above the tick); none is used with interrupts, and none may
    // sit at or above the tick's step plan (`priorities::check`)
    c.dma_interrupt_priority = embassy_stm32::interrupt::Priority::P15;
    c
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    // to the ROM bootloader if `dfu` asked, before anything is set up
    dfu::boot_check();
    // a damaged image stops here, every output as reset left it
    seal::boot_check();
    // before embassy enables its timer's interrupt, and any of ours (the
    // NVIC needs no clock)
    priorities::apply();
    let p = embassy_stm32::init(clocks());
    // the handlers' code into SRAM: nothing above has called it (`ramcode`)
    ramcode::map();
    flash_accelerator_on();
    // The settings first (they say which level of ENABLE is inactive), then
    // the outputs, inactive, before anything else runs. Until then the pins
    // float and the board's pull resistor holds ENABLE inactive.
    let (config, loaded, flash, cam) = settings::load(p.FLASH);
    let pins = drivers::outputs_inactive(p.PB13, config.enable_active_high);
    drivers::x_outputs(p.PB4, p.PB5);
    info!(
        "polyturn {} on STM32F411 (tick {} Hz): ratio {}/{}, {} edges, encoder {} counts, motor {} steps, settings {}",
        env!("CARGO_PKG_VERSION"),
        board::TICK_HZ,
        config.ratio.num(),
        config.ratio.den(),
        config.edges,
        config.encoder_counts_per_rev,
        config.motor_steps_per_rev,
        loaded
    );
    drivers::lathe_encoder(p.TIM3, p.PA6, p.PA7, p.PB0);
    drivers::cutter_encoder(p.TIM4, p.PB6, p.PB7);
    drivers::step_output(p.TIM1, p.PA8, p.PA9, p.TIM2);
    bldc::init(p.TIM10, p.PB8, p.PB1, &config);
    safety::inputs(p.PB14, p.PB15);
    if !priorities::check() {
        defmt::error!("an interrupt sits at the tick's or its step plan's level (above): fix board::PRIORITIES");
    }
    tick::start(config, pins);
    let cam = cam.filter(|(h, t)| match tick::fit_cam(h, t) {
        Some(Ok(())) => true,
        _ => {
            warn!("the stored cam table does not fit these settings: X axis off");
            false
        }
    });

    let bench = selftest::init(p.PA2, p.PA3, p.PA4);
    let low = PLANNER.start(interrupt::USART6);
    if let Ok(t) = service::service(bench) {
        low.spawn(t);
    }
    let key_pins = keys::KeyPins { engage: p.PB12, stop: p.PB10, plus: p.PB9, minus: p.PA15 };
    if let Ok(t) = keys::read(key_pins) {
        low.spawn(t);
    }

    let mut dog = IndependentWatchdog::new(p.IWDG, WATCHDOG_US);
    dog.unleash();
    if let Ok(t) = usb::console(p.USB_OTG_FS, p.PA12, p.PA11, flash, cam) {
        spawner.spawn(t);
    }
    if let Ok(t) = report::every_second() {
        spawner.spawn(t);
    }
    // PC13's LED is active low, an external one on PA10 active high;
    // `led::lit` says what they show
    let led =
        embassy_stm32::gpio::Output::new(p.PC13, embassy_stm32::gpio::Level::High, embassy_stm32::gpio::Speed::Low);
    let ext_led =
        embassy_stm32::gpio::Output::new(p.PA10, embassy_stm32::gpio::Level::Low, embassy_stm32::gpio::Speed::Low);
    if let Ok(t) = heartbeat::run(dog, led, ext_led) {
        spawner.spawn(t);
    }
}
