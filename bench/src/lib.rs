//! polyturn's test bench: what the tests run the product against, kept out
//! of the product's crates so that the `polyturn` CLI ships none of it.
//!
//! - `fakeboard`: the real sync core's console and controller behind the
//!   firmware's framing, with a machine that lets time pass (the CLI's
//!   device tests, the web page's simulated board, `fake-board` by hand);
//! - `flash`: a fake STM32F411 ROM bootloader (DfuSe) and test images;
//! - `hwsim`: the firmware's step output on the chip model
//!   (`polyturn-stm32-model`), judged by a stepper driver's rules;
//! - `peers`: other projects' gearbox algorithms beside polyturn's core.

pub mod fakeboard;
pub mod flash;
pub mod hwsim;
pub mod peers;
