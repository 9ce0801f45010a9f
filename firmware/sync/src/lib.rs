//! polyturn sync core: the exact electronic gearbox between a lathe's encoder
//! and a cutter spindle. `no_std`, no HAL, no allocation; the same code runs in
//! the firmware's control interrupt and in the host simulator.
#![no_std]

#[cfg(test)]
extern crate std;

#[macro_use]
mod fmt;

pub mod cam;
pub mod cam_upload;
pub mod check;
pub mod codec;
pub mod config;
pub mod console;
pub mod controller;
pub mod derived;
pub mod drive;
pub mod encoder;
pub mod estimator;
pub mod follower;
pub mod gear;
pub mod ratio;
pub mod selftest;
pub mod state;
pub mod steps;

/// Limits `x` to ±`limit` without the panic path of `clamp` (which
/// asserts min ≤ max): the control tick has no reachable panic.
#[inline(always)]
pub(crate) fn bound(x: i64, limit: i64) -> i64 {
    x.max(-limit).min(limit)
}

pub use config::{Config, ConfigError, DriveKind, Sense};
pub use controller::{Controller, Refusal, Stall, Status, TickInput, TickOutput, XAxis};
pub use derived::Timing;
pub use ratio::{Ratio, RatioError};
pub use state::{Fault, State};
