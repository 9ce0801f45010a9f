//! Settings in the last two 128 KiB flash sectors (6 and 7), through the
//! host-tested power-fail-safe store.

use embassy_stm32::flash::{Blocking, Flash};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use polyturn_firmware::store::{self, Loaded, SlotFlash};
use polyturn_sync::Config;

/// Offsets from the start of flash of sectors 6 and 7.
const SLOTS: [u32; 2] = [0x4_0000, 0x6_0000];
const SECTOR: u32 = 0x2_0000;

/// The settings sectors; owned by the console task, the only writer.
pub struct Sectors(Flash<'static, Blocking>);

impl SlotFlash for Sectors {
    type Error = embassy_stm32::flash::Error;
    fn erase(&mut self, slot: usize) -> Result<(), Self::Error> {
        self.0.blocking_erase(SLOTS[slot], SLOTS[slot] + SECTOR)
    }
    fn write(&mut self, slot: usize, offset: u32, data: &[u8]) -> Result<(), Self::Error> {
        self.0.blocking_write(SLOTS[slot] + offset, data)
    }
    fn read(&mut self, slot: usize, offset: u32, buf: &mut [u8]) -> Result<(), Self::Error> {
        self.0.blocking_read(SLOTS[slot] + offset, buf)
    }
}

pub fn load(flash: Peri<'static, FLASH>) -> (Config, &'static str, Sectors) {
    let mut dev = Sectors(Flash::new_blocking(flash));
    let (config, how) = store::load(&mut dev);
    (config, if how == Loaded::Defaults { "defaults (none saved)" } else { "loaded from flash" }, dev)
}

/// Saves (the console only asks while idle with the lathe at rest: the
/// erase stalls the CPU for up to 2 s).
pub fn save(dev: &mut Sectors, config: &Config) -> bool {
    store::save(dev, config).is_ok()
}
