//! A software model of the STM32F411, written from the reference manual
//! RM0383 (cross-checked with RM0090/RM0401, whose TIM1/TIM2/DMA chapters
//! describe the same IP) to serve as a test oracle for firmware that drives
//! it. It is not derived from the firmware. Its parts:
//! * [`Mcu`]: TIM1, TIM2, TIM9, TIM11 and DMA2 stream 5, cycle-exact, driven like
//!   the hardware: 32-bit register writes and reads at their bus addresses
//!   ([`addr`]), and [`Mcu::step`] advances one timer-kernel clock (CK_INT = 96 MHz
//!   for every timer);
//! * [`chip`]: the rest of the chip as the emulator (`emu/`) needs it, event-driven:
//!   GPIO, SYSCFG and EXTI, RCC and PWR, the IWDG, TIM3–5 and TIM10, USB OTG FS, and
//!   the Cortex-M4's NVIC, SCB and DWT (PM0214);
//! * [`flash`]: the flash interface's sector erase, in nanoseconds, on its own bus;
//! * [`encoder`]: TIM3's encoder interface, fed with pin levels.
//!
//! Every behaviour cites its section in doc comments.
//!
//! # Assumptions of the `Mcu`
//! * Its pins are its timers' alone (GPIO and alternate functions are [`chip`]'s):
//!   PA8/PA9 are taken to be in alternate function TIM1 (CH1/CH2), PA2/PA3 in
//!   TIM9's (CH1/CH2). A pin the timer does not drive (CCxE = 0 or MOE = 0, RM0383
//!   §12.4.9) reads `false`, as the board's pull-downs hold it low.
//! * OCxREF follows the counter in the same cycle (no extra output synchronisation
//!   stage: the manual's waveforms show none).
//! * A write to a register or field that is not modelled panics with its address; bits
//!   that are "reserved, must be kept at reset value" must be written 0. The rc_w0
//!   status registers accept 1s anywhere (writing 1 has no effect, §12.4.5).
//! * Where the manual gives no figure it is a [`Params`] field with a documented default.
//! * Order within a cycle: TIM1 counts, TIM2 samples TIM1's TRGO of the same cycle
//!   (then delays it by its resynchronisation), TIM11 counts, then DMA transfers due in
//!   that cycle land; TIM9 counts after TIM11 (it has no link to the others). A CPU
//!   write happens between two cycles and acts at once.
//! * Output-compare match modes act only on counter ticks (a CCRx or CNT write that
//!   makes CNT = CCRx is not a match); the manual does not say either way.
//!
//! # Not modelled by the `Mcu` (writing such a configuration panics)
//! Down/center-aligned counting, slave modes other than TIM2's external clock mode 1 on
//! ITR0, input capture, channels 3/4 of TIM1 and TIM11's channel, PWM modes on TIM9,
//! TIM9's slave modes, complementary outputs,
//! dead time, break, LOCK, OSSI, OCxCE/ETR, TRGO of TIM2/TIM11, CCxDE/COMDE/TDE DMA
//! requests, DMA streams other than DMA2 stream 5, FIFO mode, bursts, double buffer,
//! peripheral flow control, PINC, peripheral addresses outside TIM1. Its timers' flags
//! and interrupt-enable bits are kept; delivering the interrupts is [`chip`]'s NVIC's
//! and the emulator's.

pub mod chip;
mod dma;
pub mod encoder;
pub mod flash;
mod mcu;
mod tim1;
mod tim11;
mod tim2;
mod tim9;
mod timebase;

pub use mcu::{Edge, Mcu, NdtrReading, Params, PinId};
/// The register addresses and fields the model decodes: the firmware's own
/// table (`polyturn-regs`, checked against ST's SVD there).
pub use polyturn_regs::{addr, bits};

/// What OCxREF does when OCxM is switched into a PWM mode while the timer runs.
///
/// RM0383 §12.3.10 says that in PWM mode "TIMx_CNT and TIMx_CCRx are always compared",
/// i.e. OCxREF follows the comparison at once ([`Reevaluate`](Self::Reevaluate), the
/// default). The OCxM bit description in the same IP's manuals (RM0008/RM0090 TIMx_CCMR1
/// note, RM0367/RM0453 §"PWM mode") restricts it: "the OCREF level changes only when the
/// result of the comparison changes or when the output compare mode switches from
/// 'frozen' mode to 'PWM' mode" ([`OnlyFromFrozen`](Self::OnlyFromFrozen)): leaving a
/// forced mode for PWM then keeps the forced level until the next compare or overflow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PwmModeSwitch {
    #[default]
    Reevaluate,
    OnlyFromFrozen,
}

/// Which count an input capture latches when its edge is also one the encoder interface
/// counts: channel 1 capturing on TI1FP1's rising edge with the counter in encoder mode
/// (TIM3 timing the lathe's A rises). §13.3.5 says "the TIMx_CCR1 register gets the value
/// of the counter on the active transition", §13.3.12 that the same transition clocks
/// the counter; neither says whether the latch takes CNT before or after that count. The
/// firmware works either way (`polyturn_sync::edges::boundary_half_counts`); the bench
/// procedure ("Bench check of the lathe's edge times") records which the silicon does.
/// Default [`CountBefore`](Self::CountBefore): the capture and the count come from the
/// same synchronised edge, and the latch is taken as sampling CNT as it stood.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum EncoderCapture {
    #[default]
    CountBefore,
    CountAfter,
}

/// What clearing OCxPE does to a value waiting in TIMx_CCRx's preload. The manual says
/// a CCRx written with OCxPE = 0 "is loaded permanently" and that with OCxPE = 1 the
/// preload "is loaded in the active register at each update event" (TIMx_CCMR1 OC1PE,
/// §13.4.7 / §14.5.5); it says nothing of the moment OCxPE is cleared. The firmware's
/// words must be right under both readings (`polyturn_firmware::bldcout::stop_ops`):
/// [`AtOnce`](Self::AtOnce), the default, puts the waiting value in force as OCxPE is
/// cleared (as the TIM9 model and ARPE, §14.3.1); [`Stays`](Self::Stays) keeps the value
/// in force until the next CCRx write or update event.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PreloadClear {
    #[default]
    AtOnce,
    Stays,
}

/// Panic for a register, field or configuration the model does not implement.
#[track_caller]
pub(crate) fn unmodelled(what: &str) -> ! {
    panic!("stm32-model: not modelled: {what}")
}

/// Panic if a write to register `reg` of `timer` (at `base + o`) sets a bit
/// outside `allowed` (reserved, or not modelled).
#[track_caller]
pub(crate) fn only_bits(timer: &str, base: u32, o: u32, reg: &str, value: u32, allowed: u32) {
    if value & !allowed != 0 {
        let a = base + o;
        unmodelled(&format!("write {value:#x} to {timer}_{reg} ({a:#010x}) sets bits {:#x}", value & !allowed));
    }
}
