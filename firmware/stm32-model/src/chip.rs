//! The rest of the chip as the emulator (`emu/`) needs it: GPIO ports, SYSCFG and
//! EXTI, RCC with PWR and the flash interface's ACR, IWDG, the CRC unit, the general-purpose
//! timers TIM3/TIM4/TIM5/TIM10, and the Cortex-M4's NVIC, SCB, MPU and DWT cycle counter.
//! TIM1, TIM2, TIM9, TIM11 and DMA2 stream 5 are [`crate::Mcu`]'s, cycle-exact.
//!
//! These models are event-driven: a time-dependent one is told the CPU cycle count
//! (`advance`) and says when it next raises a flag (`next_event`), so an emulator
//! can run the CPU in slices between events. Each behaviour cites its section of
//! RM0383 (or PM0214 for the core's peripherals) and has a test here.

pub mod crc;
pub mod exti;
pub mod gpio;
pub mod gptimer;
pub mod iwdg;
pub mod mpu;
pub mod nvic;
pub mod otg;
pub mod rcc;
mod regfile;

pub use regfile::RegFile;
