//! The lathe encoder's edge times, latched in hardware: at every rising edge
//! of A the count (TIM3_CCR1) and the time in µs (TIM5_CCR3), with no DMA,
//! no interrupt and no wire (`polyturn_sync::edges` says what the core does
//! with them).
//!
//! * **The count.** TIM3 decodes A/B in encoder mode 3 (SMS = 011, §13.3.12)
//!   with channel 1 an input on TI1 (CC1S = 01, which the encoder interface
//!   needs anyway) and its capture enabled on the rising edge (CC1E = 1,
//!   CC1P = CC1NP = 0, §13.4.9): CCR1 "gets the value of the counter on the
//!   active transition" (§13.3.5). Whether that is the count before or after
//!   the count the same edge makes, the manual does not say: the core does
//!   not need to know (`edges::boundary_half_counts`), the bench records it.
//! * **The time.** TIM3's CR2.MMS = 011 "compare pulse" (§13.4.2): TRGO
//!   pulses "when the CC1IF flag is to be set (even if it was already high),
//!   as soon as a capture ... occurred". TIM5, embassy's time driver (PSC so
//!   it counts at `STAMP_HZ`, ARR = 0xFFFF, CC1 and CC2 only: it never
//!   writes SMCR, CCMR2 or CCER), takes that pulse on ITR1 (TS = 001: the
//!   table "TIMx internal trigger connection", §13.4.3, TIM5 row: ITR0 TIM2,
//!   ITR1 TIM3, ITR2 TIM4) with its slave mode off (SMS = 000: the counter is
//!   embassy's, untouched), and channel 3 captures on TRC (CC3S = 11,
//!   §13.4.8; CC3E = 1): CCR3 is the µs of A's last rise.
//! * **Embassy's interrupt** clears TIM5's flags by writing SR = !SR, so it
//!   may clear CC3IF and CC3OF (§13.4.5, rc_w0), which nobody reads; CC3IE
//!   stays 0, so the captures raise no interrupt of its. Whether a capture
//!   has happened at all is TIM3's CC1IF instead (`read::Gate`), which
//!   nothing clears but a read of CCR1.
//!
//! `program` holds the configuration the MCU applies verbatim after
//! embassy's set-up (the model runs the same words:
//! `firmware/stm32-model/tests/edgetime.rs`); `read` the tick's read of the
//! pair; `start` the measurements that tie the stamps to the ticks.

pub mod program;
pub mod read;
pub mod start;
pub mod watch;

use crate::board::TICK_HZ;
use crate::clocks::CLOCKS;

/// TIM5's count rate: embassy-time's tick rate (`app::tick` checks the two
/// are equal), one stamp a µs.
pub const STAMP_HZ: u32 = 1_000_000;
/// TIM5's kernel clock (APB1's timers, `clocks`).
pub const TIM5_CLOCK_HZ: u32 = CLOCKS.apb1_timer_hz();
/// Stamps per control tick: 50 at 20 kHz.
pub const STAMPS_PER_TICK: u16 = (STAMP_HZ / TICK_HZ) as u16;

// A tick is a whole number of stamps and TIM11's period a whole number of
// TIM5 prescaler periods, so every tick's instant falls on a stamp: 4 800
// cycles = 50 × 96 at 20 kHz.
const _: () = {
    assert!(TIM5_CLOCK_HZ.is_multiple_of(STAMP_HZ));
    assert!(STAMP_HZ.is_multiple_of(TICK_HZ));
    let tick_cycles = CLOCKS.apb2_timer_hz() / TICK_HZ;
    assert!(CLOCKS.apb2_timer_hz().is_multiple_of(TICK_HZ));
    assert!(tick_cycles == STAMPS_PER_TICK as u32 * (TIM5_CLOCK_HZ / STAMP_HZ));
};

/// Register blocks (RM0383 §2.3 Table 1; TIM11 is the tick's, as the
/// step output programs it), their registers' offsets (§13.4.21,
/// §14.5.12), and GPIOA_IDR (§8.4.5).
pub use polyturn_regs::addr::{off, GPIOA, GPIOA_IDR, TIM11, TIM3, TIM5};

/// A's and B's bits in GPIOA_IDR (PA6, PA7: `board::PINS`).
pub const A_PIN: u32 = 6;
pub const B_PIN: u32 = 7;

#[cfg(test)]
mod start_tests;
#[cfg(test)]
mod tests;
