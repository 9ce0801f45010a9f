//! Settings in the last two 128 KiB flash sectors (6 and 7), through the
//! host-tested power-fail-safe store.

use super::mmio::Mmio;
use embassy_stm32::flash::{Blocking, Flash};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use polyturn_firmware::flashprog::{self, SettingsSector};
use polyturn_firmware::regs::apply;
use polyturn_firmware::store::{self, Loaded, SlotFlash, CAM_POINTS_AT};
use polyturn_sync::cam_upload::CamHeader;
use polyturn_sync::Config;

/// A cam table in flash: its header and its points, mapped in place.
pub type StoredCam = (CamHeader, &'static [i32]);
const FLASH_BASE: u32 = 0x0800_0000;

/// The settings' two slots: sectors 6 and 7 (`SettingsSector::offset`).
const SLOTS: [SettingsSector; 2] = [SettingsSector::Six, SettingsSector::Seven];

/// The settings sectors; owned by the console task, the only writer.
pub struct Sectors(Flash<'static, Blocking>);

/// Runs a flash erase or write with the data cache off, then resets it
/// before turning it back on (RM0383 §3.4 and FLASH_ACR §3.8.1: the data
/// cache is not kept coherent with flash being programmed, and DCRST acts
/// only while it is off); embassy does this only for dual-bank parts. The
/// instruction cache is left alone: sectors 6 and 7 hold no code.
fn cache_off<R>(f: impl FnOnce() -> R) -> R {
    use embassy_stm32::pac::FLASH;
    let on = FLASH.acr().read().dcen();
    FLASH.acr().modify(|w| w.set_dcen(false));
    let r = f();
    if on {
        FLASH.acr().modify(|w| w.set_dcrst(true));
        FLASH.acr().modify(|w| w.set_dcrst(false));
        FLASH.acr().modify(|w| w.set_dcen(true));
    }
    r
}

/// Why a flash operation failed.
#[derive(Debug, defmt::Format)]
pub enum FlashError {
    /// the erase program stopped at this step (`flashprog::erase_sector`)
    Erase(usize),
    Write(embassy_stm32::flash::Error),
}

impl SlotFlash for Sectors {
    type Error = FlashError;
    fn erase(&mut self, slot: usize) -> Result<(), FlashError> {
        // The erase stalls the CPU for up to 2 s (×32, `flashprog`): the
        // watchdog starts a full period now; its shortest real period is
        // 5.4 s (`iwdg`, tests/flash_erase.rs checks the margin). Our own
        // program, not embassy's erase, which runs at ×8 (twice as long).
        embassy_stm32::pac::IWDG.kr().write(|w| w.set_key(embassy_stm32::pac::iwdg::vals::Key::RESET));
        let program = flashprog::erase_sector(SLOTS[slot]);
        cache_off(|| apply(&program, &mut Mmio)).map_err(|step| {
            let _ = apply(&flashprog::LOCK, &mut Mmio);
            FlashError::Erase(step)
        })
    }
    fn write(&mut self, slot: usize, offset: u32, data: &[u8]) -> Result<(), FlashError> {
        cache_off(|| self.0.blocking_write(SLOTS[slot].offset() + offset, data)).map_err(FlashError::Write)
    }
    fn read(&mut self, slot: usize, offset: u32, buf: &mut [u8]) -> Result<(), FlashError> {
        self.0.blocking_read(SLOTS[slot].offset() + offset, buf).map_err(FlashError::Write)
    }
}

pub fn load(flash: Peri<'static, FLASH>) -> (Config, &'static str, Sectors, Option<StoredCam>) {
    let mut dev = Sectors(Flash::new_blocking(flash));
    let (config, how) = store::load(&mut dev);
    let cam = newest_cam(&mut dev, how);
    (config, if how == Loaded::Defaults { "defaults (none saved)" } else { "loaded from flash" }, dev, cam)
}

/// The cam table saved with the newest settings, checked, mapped in place.
fn newest_cam(dev: &mut Sectors, how: Loaded) -> Option<StoredCam> {
    let Loaded::Saved { slot, .. } = how else { return None };
    let h = store::load_cam(dev, slot)?;
    let at = (FLASH_BASE + SLOTS[slot].offset() + CAM_POINTS_AT) as *const i32;
    // SAFETY: memory-mapped flash, 4-byte aligned, checked by its CRC just
    // now; this slot is not erased until a later save makes it the older
    // one, and every save re-fits the cam from the new slot first.
    Some((h, unsafe { core::slice::from_raw_parts(at, h.points as usize) }))
}

/// Saves (the console only asks while idle with the lathe at rest: the
/// erase stalls the CPU for up to 2 s, `flashprog`).
/// Returns the cam table as stored in the new slot (re-fit it from there).
pub fn save(dev: &mut Sectors, config: &Config, cam: Option<(CamHeader, &[i32])>) -> Result<Option<StoredCam>, ()> {
    store::save(dev, config, cam).map_err(|e| defmt::warn!("settings not saved: {}", e))?;
    let (_, how) = store::load(dev);
    Ok(newest_cam(dev, how))
}
