//! polyturn firmware: the board-independent, host-testable parts.
//!
//! Everything here compiles on the PC and is tested there; only `main.rs` and
//! the `app` module touch registers (and only on the MCU).
#![cfg_attr(not(test), no_std)]

pub mod bldcout;
pub mod board;
pub mod clocks;
pub mod dfu;
pub mod edgetime;
pub mod flashprog;
pub mod iwdg;
pub mod keys;
pub mod led;
pub mod line;
pub mod quadgen;
pub mod regs;
pub mod seal;
pub mod stepgen;
pub mod store;
pub mod xsteps;
