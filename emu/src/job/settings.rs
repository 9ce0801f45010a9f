//! A settings record written into the emulated flash before boot with the
//! firmware's own store and codec (`polyturn_firmware::store::save`), into the
//! sectors the firmware keeps them in (`flashprog::SettingsSector`).

use crate::image::FLASH_BASE;
use polyturn_firmware::flashprog::SettingsSector;
use polyturn_firmware::store::{self, SlotFlash, SLOT_LEN};
use polyturn_sync::Config;

/// Two slots of erased flash.
struct Slots([Vec<u8>; 2]);

impl SlotFlash for Slots {
    type Error = ();
    fn erase(&mut self, slot: usize) -> Result<(), ()> {
        self.0[slot].fill(0xFF);
        Ok(())
    }
    fn write(&mut self, slot: usize, offset: u32, data: &[u8]) -> Result<(), ()> {
        let o = offset as usize;
        self.0[slot].get_mut(o..o + data.len()).ok_or(())?.copy_from_slice(data);
        Ok(())
    }
    fn read(&mut self, slot: usize, offset: u32, buf: &mut [u8]) -> Result<(), ()> {
        let o = offset as usize;
        buf.copy_from_slice(self.0[slot].get(o..o + buf.len()).ok_or(())?);
        Ok(())
    }
}

/// The flash contents (address, bytes) that hold `cfg` as saved settings.
pub fn saved(cfg: &Config) -> Result<Vec<(u32, Vec<u8>)>, String> {
    let mut slots = Slots([vec![0xFF; SLOT_LEN], vec![0xFF; SLOT_LEN]]);
    store::save(&mut slots, cfg, None).map_err(|_| "the firmware's store refused the settings".to_string())?;
    let [a, b] = slots.0;
    Ok(vec![(FLASH_BASE + SettingsSector::Six.offset(), a), (FLASH_BASE + SettingsSector::Seven.offset(), b)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use polyturn_firmware::store::Loaded;

    #[test]
    fn the_saved_sectors_load_back_through_the_firmwares_store() {
        // (at 11/3 the default top lathe speed would overspeed the motor: refused)
        let cfg =
            Config { ratio: polyturn_sync::Ratio::parse("11/3").unwrap(), max_lathe_rpm: 390, ..Config::default() };
        let flash = saved(&cfg).unwrap();
        assert_eq!(flash[0].0, 0x0804_0000, "sector 6 (RM0383 §3.3 table 4)");
        assert_eq!(flash[1].0, 0x0806_0000, "sector 7");
        let mut slots = Slots([flash[0].1.clone(), flash[1].1.clone()]);
        let (loaded, how) = store::load(&mut slots);
        assert_eq!(loaded, cfg);
        assert!(matches!(how, Loaded::Saved { .. }));
    }
}
