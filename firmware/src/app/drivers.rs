//! Register-level drivers behind the sync core's seams (emit a step plan,
//! read the pulses emitted; the tick reads the encoder counters and the
//! lathe's edge times itself). Only register writes live here; their values
//! come from host-tested code.

use super::mmio::Mmio;
use embassy_stm32::gpio::{Level, Output, OutputType, Speed};
use embassy_stm32::pac;
use embassy_stm32::pac::timer::vals::FilterValue;
use embassy_stm32::peripherals as P;
use embassy_stm32::timer::qei::{Qei, QeiMode};
use embassy_stm32::timer::simple_pwm::PwmPin;
use embassy_stm32::Peri;
use polyturn_firmware::edgetime;
use polyturn_firmware::stepgen;
use polyturn_firmware::stepgen::program::Bus;
use polyturn_sync::steps::Dir;

/// Timer clock (APB1 ×2 and APB2 ×1 both give the system clock: `clocks`).
pub const TIMER_HZ: u32 = polyturn_firmware::clocks::TIMING.step_timer_hz;
const ENABLE_PIN: usize = 13;
const X_STEP_PIN: usize = 4;
const X_DIR_PIN: usize = 5;

/// X STEP (PB4) and DIR (PB5) as outputs, low.
pub fn x_outputs(step: Peri<'static, P::PB4>, dir: Peri<'static, P::PB5>) {
    core::mem::forget(Output::new(step, Level::Low, Speed::High));
    core::mem::forget(Output::new(dir, Level::Low, Speed::High));
}

/// The X pins for this tick, in one BSRR write.
pub fn set_x_pins(p: polyturn_firmware::xsteps::XPins) {
    pac::GPIOB.bsrr().write(|w| {
        if p.step_high {
            w.set_bs(X_STEP_PIN, true)
        } else {
            w.set_br(X_STEP_PIN, true)
        }
        if p.dir == Dir::Forward {
            w.set_bs(X_DIR_PIN, true)
        } else {
            w.set_br(X_DIR_PIN, true)
        }
    });
}

/// ENABLE as an output at its inactive level for the configured polarity
/// (through reset the board's pull resistor holds it).
pub fn outputs_inactive(enable: Peri<'static, P::PB13>, active_high: bool) -> OutputPins {
    let inactive = if active_high { Level::Low } else { Level::High };
    core::mem::forget(Output::new(enable, inactive, Speed::Low));
    let mut pins = OutputPins { enable_active_high: false };
    pins.set_polarity(active_high);
    pins
}

#[derive(Clone, Copy)]
pub struct OutputPins {
    pub enable_active_high: bool,
}

/// The ENABLE polarity, for the panic handler (which has no other state).
static ENABLE_ACTIVE_HIGH: core::sync::atomic::AtomicBool = core::sync::atomic::AtomicBool::new(false);

/// The step output and the BLDC drive stopped at once, from the E-stop's
/// interrupt: TIM1's counter first, so no STEP rises after it, then the
/// BLDC's stop and the rest of the halt. A STEP pulse that was high is
/// released by the tick once it has had its width (`stepgen`): nothing
/// here waits.
pub fn stop_actuators() {
    stop_step_timer();
    super::bldc::stop();
    halt_steps();
}

/// Everything off, where nothing runs after (the panic and fault handlers):
/// no more steps, the BLDC drive's stop, a high STEP pulse released after
/// its width (the one wait, up to `pulse`, 100 µs: no tick comes to do it),
/// ENABLE inactive.
pub fn all_outputs_off() {
    stop_step_timer();
    super::bldc::stop();
    let pulse = HALT_PULSE.load(core::sync::atomic::Ordering::Relaxed);
    let _ = stepgen::program::apply(&stepgen::program::halt_and_wait(pulse), &mut Mmio);
    pac::GPIOB.bsrr().write(|w| w.set_br(X_STEP_PIN, true));
    let pins = OutputPins { enable_active_high: ENABLE_ACTIVE_HIGH.load(core::sync::atomic::Ordering::Relaxed) };
    pins.set_enable(false);
}

impl OutputPins {
    /// Sets the active level, also for the panic handler (not per tick).
    pub fn set_polarity(&mut self, active_high: bool) {
        self.enable_active_high = active_high;
        ENABLE_ACTIVE_HIGH.store(active_high, core::sync::atomic::Ordering::Relaxed);
    }

    pub fn set_enable(&self, on: bool) {
        let high = on == self.enable_active_high;
        pac::GPIOB.bsrr().write(|w| if high { w.set_bs(ENABLE_PIN, true) } else { w.set_br(ENABLE_PIN, true) });
    }
}

/// TIM4's input filter (TIM3's is in `edgetime::program`'s words).
fn encoder_filter(t: pac::timer::TimGp16) {
    // 8 samples at 96 MHz: rejects glitches under 83 ns, passes > 1 MHz edges.
    t.ccmr_input(0).modify(|w| {
        w.set_icf(0, FilterValue::FCK_INT_N8);
        w.set_icf(1, FilterValue::FCK_INT_N8);
    });
}

/// The lathe encoder on TIM3, with its index and its edge times. Embassy's
/// Qei takes the pins (A, B: AF2) and TIM3's clock and starts it in encoder
/// mode 3; then `edgetime::program::CONFIG`, verbatim: TIM3's whole input
/// configuration (the filters, the index on channel 3, the count captured
/// on channel 1 at A's rise, TRGO's compare pulse) and TIM5's capture of
/// that pulse, its time (after embassy's time driver set TIM5 up, in
/// `embassy_stm32::init`).
pub fn lathe_encoder(
    tim: Peri<'static, P::TIM3>,
    a: Peri<'static, P::PA6>,
    b: Peri<'static, P::PA7>,
    index: Peri<'static, P::PB0>,
) {
    let cfg = embassy_stm32::timer::qei::Config { mode: QeiMode::Mode3, ..Default::default() };
    core::mem::forget(Qei::new(tim, a, b, cfg));
    index_pin(index);
    let _ = edgetime::program::apply(&edgetime::program::CONFIG, &mut Mmio);
}

/// The index on PB0 = TIM3_CH3 (AF2, DS10314 table 9), pulled down: channel
/// 3 captures the encoder count at the index's rising edge in hardware
/// (RM0383 §13.3.5; `edgetime::program` sets the channel up), so the
/// latched count does not wait for any interrupt.
fn index_pin(pin: Peri<'static, P::PB0>) {
    let _ = pin;
    pac::GPIOB.pupdr().modify(|w| w.set_pupdr(0, pac::gpio::vals::Pupdr::PULL_DOWN));
    pac::GPIOB.afr(0).modify(|w| w.set_afr(0, 2));
    pac::GPIOB.moder().modify(|w| w.set_moder(0, pac::gpio::vals::Moder::ALTERNATE));
}

/// TIM3_SR, read once a tick for the index (CC3IF) and the edge times'
/// gate (CC1IF, `edgetime::read::Gate`), before CCR1 or CCR3 is read.
#[inline(always)]
pub fn lathe_flags() -> u32 {
    pac::TIM3.sr().read().0
}

/// The lathe count latched at the last index edge, once (reading CCR3
/// clears CC3IF, §13.4.5), from the flags `lathe_flags` read.
#[inline(always)]
pub fn index(flags: u32) -> Option<u16> {
    (flags & edgetime::program::CC3IF != 0).then(|| pac::TIM3.ccr(2).read().ccr())
}

pub fn cutter_encoder(tim: Peri<'static, P::TIM4>, a: Peri<'static, P::PB6>, b: Peri<'static, P::PB7>) {
    let cfg = embassy_stm32::timer::qei::Config { mode: QeiMode::Mode3, ..Default::default() };
    core::mem::forget(Qei::new(tim, a, b, cfg));
    encoder_filter(pac::TIM4);
}

/// The STEP pulse width in timer cycles, for halts from outside the tick.
static HALT_PULSE: core::sync::atomic::AtomicU32 = core::sync::atomic::AtomicU32::new(0);

/// Sets the pulse width `halt_steps` waits out (at start and on changes).
pub fn set_halt_pulse(cycles: u32) {
    HALT_PULSE.store(cycles, core::sync::atomic::Ordering::Relaxed);
}

/// `program::STOP` alone: no STEP pulse rises after it (the E-stop's first
/// write; `halt_steps` follows).
#[inline(always)]
pub fn stop_step_timer() {
    if let stepgen::program::Op::Write(addr, value) = stepgen::program::STOP {
        Mmio.write(addr, value);
    }
}

/// Stops the step output from any context (E-stop, a late plan): no pulse
/// rises after it; a high one is released at full width by a later tick
/// (`Generator::halted_elsewhere`).
pub fn halt_steps() {
    let _ = stepgen::program::apply(&stepgen::program::HALT_IN_RAM, &mut Mmio);
}

/// RAM the DMA reads TIM1's segments from (only through `Mmio`).
pub struct Ring(core::cell::UnsafeCell<[u32; stepgen::program::RING_WORDS as usize]>);
// SAFETY: written only by the tick and its step plan, which never run at
// once (`tick::plan`), through volatile writes; read by the DMA.
unsafe impl Sync for Ring {}
static RING: Ring = Ring(core::cell::UnsafeCell::new([0; stepgen::program::RING_WORDS as usize]));

pub fn ring_address() -> u32 {
    RING.0.get() as u32
}

/// TIM1 CH1 (PA8) is STEP and CH2 (PA9) is DIR, both fed by DMA2 stream 5;
/// TIM2, clocked by TIM1's OC1REF through ITR0, counts the pulses. Nothing
/// runs until the first tick arms the generator.
pub fn step_output(
    t1: Peri<'static, P::TIM1>,
    step: Peri<'static, P::PA8>,
    dir: Peri<'static, P::PA9>,
    t2: Peri<'static, P::TIM2>,
) {
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(t1));
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(t2));
    pac::RCC.ahb1enr().modify(|w| w.set_dma2en(true));
    // PA8/PA9 to TIM1 (AF1); the timer drives them only once armed
    core::mem::forget(PwmPin::new(step, OutputType::PushPull));
    core::mem::forget(PwmPin::new(dir, OutputType::PushPull));
    let _ = stepgen::program::apply(&stepgen::program::COUNTER_INIT, &mut Mmio);
}

/// TIM2's count of STEP pulses, for the core's check.
pub fn steps_counted() -> u16 {
    pac::TIM2.cnt().read() as u16
}
