//! The MCU half of `polyturn_firmware::seal`: at boot the image checks
//! itself with the CRC unit, and a damaged one never runs: every output
//! stays as reset left it, and the LEDs show `led::damaged` until the
//! board is flashed again (BOOT0 and `polyturn flash`, docs/src/flashing.md).

use super::mmio::Mmio;
use polyturn_firmware::{led, seal};

extern "C" {
    /// cortex-m-rt's link.x: `.data`'s initial values are stored in flash
    /// from `__sidata` (its LMA, after `.rodata`), and run from
    /// `__sdata..__edata` in RAM. They are the last bytes of the image.
    static __sidata: u32;
    static __sdata: u32;
    static __edata: u32;
}

/// Where the link put the image's last byte, so where its seal lies.
fn image_end() -> u32 {
    let at = |p: *const u32| p as usize as u32;
    let (sidata, sdata, edata) = (at(&raw const __sidata), at(&raw const __sdata), at(&raw const __edata));
    sidata.wrapping_add(edata.wrapping_sub(sdata))
}

/// Runs before anything is set up; returns only for a whole image, or an
/// unsealed one under the debugger that wrote it (`seal::probes_own`). No
/// log for a damaged image: its `.data` (where the log's RTT block starts)
/// may be erased flash, and the light says it.
pub fn boot_check() {
    match seal::verify(&mut Mmio, image_end()) {
        Ok(()) => {}
        Err(damage) if seal::probes_own(&mut Mmio, damage) => {
            defmt::warn!("this image has no seal (a probe wrote the ELF): it runs because a debugger is attached");
        }
        Err(_) => damaged(),
    }
}

/// The damaged image's light, for ever: nothing else runs (no interrupt
/// is enabled, the watchdog is not started), every other pin is an input.
fn damaged() -> ! {
    // the HSI's cycles per step (nothing switched the clock yet)
    const STEP: u32 = seal::HSI_HZ / 1000 * led::DAMAGED_STEP_MS;
    let mut at = seal::led_setup(&mut Mmio);
    let mut ms = 0u32;
    loop {
        seal::led_on(&mut Mmio, led::damaged(ms));
        at = seal::wait(&mut Mmio, at, STEP);
        ms = (ms + led::DAMAGED_STEP_MS) % led::DAMAGED_FRAME_MS;
    }
}
