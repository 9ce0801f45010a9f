//! polyturn host tools: the geometry model (ground truth), the setup
//! planner, plant models and the simulator that runs the real sync core;
//! and the firmware image and its flashing over the ROM bootloader's USB DFU.

pub mod cli;
pub mod compensate;
pub mod flash;
pub mod geometry;
pub mod noncircular;
pub mod planner;
pub mod round;
pub mod sim;
