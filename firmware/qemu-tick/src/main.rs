//! The control tick on an emulated Cortex-M4: QEMU's netduinoplus2
//! (STM32F405) cannot boot the embassy app (no F4 clock controller), but it
//! runs the sync core's tick against a synthetic encoder and step counter.
//! Checks the gear invariant and counts instructions per tick:
//!
//!   qemu-system-arm -M netduinoplus2 -icount shift=0 -nographic \
//!     -semihosting-config enable=on,target=native -kernel <elf>
//!
//! With `-icount shift=0` every instruction takes 1 ns of virtual time;
//! SysTick runs from that clock, so counts per instruction are measured on a
//! loop of known length and tick instructions follow from SysTick counts.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod locked;
#[cfg(target_os = "none")]
mod mcu;
#[cfg(target_os = "none")]
mod meter;

#[cfg(not(target_os = "none"))]
fn main() {
    println!("polyturn-qemu-tick runs under QEMU: see .ci/qemu");
}
