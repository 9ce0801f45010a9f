//! polyturn sync core: the exact electronic gearbox between a lathe's encoder
//! and a cutter spindle. `no_std`, no HAL, no allocation; the same code runs in
//! the firmware's control interrupt and in the host simulator.
#![no_std]

#[cfg(test)]
extern crate std;

#[macro_use]
mod fmt;

pub mod angle;
pub mod cam;
pub mod cam_upload;
pub mod check;
pub mod codec;
pub mod config;
pub mod console;
pub mod controller;
pub mod derived;
pub mod drive;
pub mod edges;
pub mod encoder;
pub mod estimator;
pub mod follower;
pub mod gear;
pub mod q16;
pub mod ratio;
pub mod selftest;
pub mod state;
pub mod steps;
pub mod timing;

pub use config::{Config, ConfigError, DriveKind, Sense};
pub use controller::{Controller, Refusal, Stall, Status, TickInput, TickOutput, XAxis};
pub use ratio::{Ratio, RatioError};
pub use state::{Fault, State};
pub use timing::Timing;
