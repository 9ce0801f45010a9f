//! Register-level drivers behind the sync core's seams (read a 16-bit
//! counter, emit a step plan, read the pulses emitted). Only register
//! writes live here; their values come from host-tested code.

use embassy_stm32::gpio::{Level, Output, OutputType, Speed};
use embassy_stm32::pac;
use embassy_stm32::pac::timer::vals::{FilterValue, Mms, Ocm, Sms, Ts};
use embassy_stm32::peripherals as P;
use embassy_stm32::timer::qei::{Qei, QeiMode};
use embassy_stm32::timer::simple_pwm::PwmPin;
use embassy_stm32::Peri;
use polyturn_firmware::steptimer;
use polyturn_sync::encoder::Counter16;
use polyturn_sync::steps::{Dir, StepOutput, StepPlan};

/// Timer clock (APB1 ×2 and APB2 ×1 both give the system clock).
pub const TIMER_HZ: u32 = polyturn_firmware::board::SYSCLK_HZ;
const DIR_PIN: usize = 12;
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

/// DIR and ENABLE as outputs, ENABLE at its inactive level for the
/// configured polarity (through reset the board's pull resistor holds it).
pub fn outputs_inactive(dir: Peri<'static, P::PB12>, enable: Peri<'static, P::PB13>, active_high: bool) -> OutputPins {
    core::mem::forget(Output::new(dir, Level::Low, Speed::VeryHigh));
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

/// Everything off, from any context: no more steps, ENABLE inactive.
pub fn all_outputs_off() {
    Steps { pulse_ticks: 0 }.halt();
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
    fn set_dir(dir: Dir) {
        pac::GPIOB.bsrr().write(|w| match dir {
            Dir::Forward => w.set_bs(DIR_PIN, true),
            Dir::Reverse => w.set_br(DIR_PIN, true),
        });
    }
}

fn encoder_filter(t: pac::timer::TimGp16) {
    // 8 samples at 96 MHz: rejects glitches under 83 ns, passes > 1 MHz edges.
    t.ccmr_input(0).modify(|w| {
        w.set_icf(0, FilterValue::FCK_INT_N8);
        w.set_icf(1, FilterValue::FCK_INT_N8);
    });
}

pub fn lathe_encoder(tim: Peri<'static, P::TIM3>, a: Peri<'static, P::PA6>, b: Peri<'static, P::PA7>) {
    let cfg = embassy_stm32::timer::qei::Config { mode: QeiMode::Mode3, ..Default::default() };
    core::mem::forget(Qei::new(tim, a, b, cfg));
    encoder_filter(pac::TIM3);
}

pub fn cutter_encoder(tim: Peri<'static, P::TIM4>, a: Peri<'static, P::PB6>, b: Peri<'static, P::PB7>) {
    let cfg = embassy_stm32::timer::qei::Config { mode: QeiMode::Mode3, ..Default::default() };
    core::mem::forget(Qei::new(tim, a, b, cfg));
    encoder_filter(pac::TIM4);
}

/// The counter seams.
pub struct LatheCounter;
impl Counter16 for LatheCounter {
    fn read(&mut self) -> u16 {
        pac::TIM3.cnt().read().cnt()
    }
}
pub struct CutterCounter;
impl Counter16 for CutterCounter {
    fn read(&mut self) -> u16 {
        pac::TIM4.cnt().read().cnt()
    }
}

/// TIM1 CH1 (PA8) makes the pulses in one-pulse mode with its repetition
/// counter; TIM2, clocked by TIM1's OC1REF through ITR0, counts them.
pub fn step_generator(
    t1: Peri<'static, P::TIM1>,
    pin: Peri<'static, P::PA8>,
    t2: Peri<'static, P::TIM2>,
    _pulse_ns: u32,
) {
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(t1));
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(t2));
    core::mem::forget(PwmPin::new(pin, OutputType::PushPull));
    let t = pac::TIM1;
    t.cr1().modify(|w| {
        w.set_cen(false);
        w.set_opm(true);
    });
    t.psc().write_value(0);
    t.ccmr_output(0).modify(|w| w.set_ocm(0, Ocm::FORCE_INACTIVE));
    t.ccer().modify(|w| w.set_cce(0, true));
    t.bdtr().modify(|w| w.set_moe(true));
    t.cr2().modify(|w| w.set_mms(Mms::COMPARE_OC1));
    let c = pac::TIM2;
    c.smcr().modify(|w| {
        w.set_ts(Ts::ITR0);
        w.set_sms(Sms::EXT_CLOCK_MODE);
    });
    c.arr().write_value(u32::MAX);
    c.cr1().modify(|w| w.set_cen(true));
}

/// The step output seam over TIM1/TIM2.
pub struct Steps {
    pub pulse_ticks: u16,
}

impl StepOutput for Steps {
    fn emit(&mut self, plan: &StepPlan) {
        let Some(p) = steptimer::program(plan, self.pulse_ticks) else { return };
        let t = pac::TIM1;
        // The last pulse of the previous tick may still be high (its edge was
        // inside that tick): let it finish, at most one pulse width (OPM
        // clears CEN at its end), so the driver never sees a cut-short pulse.
        for _ in 0..512 {
            if !t.cr1().read().cen() {
                break;
            }
        }
        OutputPins::set_dir(plan.dir);
        t.cr1().modify(|w| {
            w.set_cen(false);
            w.set_arpe(false);
        });
        t.ccmr_output(0).modify(|w| {
            w.set_ocpe(0, false);
            w.set_ocm(0, Ocm::PWM_MODE2);
        });
        t.rcr().write(|w| w.set_rep(p.rcr as u16));
        t.arr().write(|w| w.set_arr(p.first_arr));
        t.ccr(0).write(|w| w.set_ccr(p.first_ccr));
        t.egr().write(|w| w.set_ug(true)); // load RCR, CNT = 0
                                           // Steady cycles go to the preload registers, taken at the first update.
        t.cr1().modify(|w| w.set_arpe(true));
        t.ccmr_output(0).modify(|w| w.set_ocpe(0, true));
        t.arr().write(|w| w.set_arr(p.arr));
        t.ccr(0).write(|w| w.set_ccr(p.ccr));
        t.sr().write_value(pac::timer::regs::SrAdv(0));
        t.cr1().modify(|w| w.set_cen(true));
    }

    fn emitted(&mut self) -> u16 {
        pac::TIM2.cnt().read() as u16
    }

    fn halt(&mut self) {
        let t = pac::TIM1;
        t.cr1().modify(|w| w.set_cen(false));
        t.ccmr_output(0).modify(|w| w.set_ocm(0, Ocm::FORCE_INACTIVE));
    }
}

/// TIM10 CH1 (PB8): ESC servo pulses at 50 Hz, 1 µs resolution.
pub fn esc_pwm(tim: Peri<'static, P::TIM10>, pin: Peri<'static, P::PB8>) {
    core::mem::forget(embassy_stm32::timer::low_level::Timer::new(tim));
    // PB8 also maps to TIM4 (the cutter encoder), so select AF3 (TIM10) by hand.
    let _ = pin;
    pac::GPIOB.moder().modify(|w| w.set_moder(8, pac::gpio::vals::Moder::ALTERNATE));
    pac::GPIOB.afr(1).modify(|w| w.set_afr(0, 3));
    let t = pac::TIM10;
    t.psc().write_value((TIMER_HZ / 1_000_000 - 1) as u16);
    t.arr().write(|w| w.set_arr(19_999));
    t.ccr(0).write(|w| w.set_ccr(1_000));
    t.ccmr_output(0).modify(|w| {
        w.set_ocm(0, Ocm::PWM_MODE1);
        w.set_ocpe(0, true);
    });
    t.ccer().modify(|w| w.set_cce(0, true));
    t.cr1().modify(|w| {
        w.set_arpe(true);
        w.set_cen(true);
    });
}

pub fn set_esc_pulse_us(us: u16) {
    pac::TIM10.ccr(0).write(|w| w.set_ccr(us));
}
