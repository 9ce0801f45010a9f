//! polyturn firmware entry point: wires the Black Pill's hardware to the sync core.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod app;

/// On a PC this binary does nothing: the logic is tested through the library.
#[cfg(not(target_os = "none"))]
fn main() {
    println!("polyturn-firmware runs on the STM32F411; build it with `cargo fw`.");
}
