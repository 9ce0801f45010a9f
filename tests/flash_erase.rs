//! The settings' sector erase (`polyturn_firmware::flashprog`) run through
//! the model of the flash interface written from RM0383 §3.5/§3.8 and
//! DS10314's erase times: the erase runs at ×32, leaves FLASH_CR locked,
//! and, with the writes after it, fits inside the watchdog's period over
//! the LSI's whole range.
use polyturn_firmware::flashprog::{self as fp, erase_sector, SettingsSector, ERASE_MAX_US, WORD_PROGRAM_MAX_US};
use polyturn_firmware::iwdg::{period_us, LSI_MAX_HZ, WATCHDOG_US};
use polyturn_firmware::regs::{apply, Bus};
use polyturn_firmware::store::SLOT_LEN;
use polyturn_stm32_model::flash::*;

/// The CPU at 96 MHz: a poll of FLASH_SR costs at least 4 cycles.
struct Cpu(Flash);

impl Bus for Cpu {
    fn write(&mut self, addr: u32, value: u32) {
        self.0.advance_ns(10);
        self.0.write(addr, value);
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.0.advance_ns(42);
        self.0.read(addr)
    }
    fn delay(&mut self, cycles: u32) {
        self.0.advance_ns(cycles as u64 * 1000 / 96);
    }
}

fn run(mut f: Flash, sector: SettingsSector) -> (Flash, Result<(), usize>) {
    let mut cpu = Cpu(f);
    let r = apply(&erase_sector(sector), &mut cpu);
    f = cpu.0;
    (f, r)
}

#[test]
fn the_settings_erase_runs_at_x32_and_leaves_flash_cr_locked() {
    for sector in [SettingsSector::Six, SettingsSector::Seven] {
        let (mut f, r) = run(Flash::new(EraseTime::Typical), sector);
        assert_eq!(r, Ok(()));
        assert_eq!(f.erases.len(), 1);
        let e = f.erases[0];
        assert_eq!((e.sector, e.psize), (sector as u32, 2), "{sector:?} at ×32");
        assert_eq!(e.end_ns - e.start_ns, 1_000_000_000, "1 s typical");
        assert_eq!(f.read(CR), CR_LOCK);
        assert_eq!(f.bus_errors, 0);
    }
}

#[test]
fn the_erase_works_when_a_failed_save_left_flash_cr_unlocked() {
    let mut f = Flash::new(EraseTime::Typical);
    f.write(KEYR, KEY1);
    f.write(KEYR, KEY2);
    let (f, r) = run(f, SettingsSector::Six);
    assert_eq!(r, Ok(()));
    assert_eq!(f.bus_errors, 0, "no key written to an unlocked register");
    assert_eq!(f.erases.len(), 1);
}

#[test]
fn the_erase_waits_for_an_operation_already_under_way() {
    // an erase of sector 7 started and left running (no wait)
    let mut f = Flash::new(EraseTime::Typical);
    f.write(KEYR, KEY1);
    f.write(KEYR, KEY2);
    let cr = CR_SER | (7 << CR_SNB_SHIFT) | (2 << CR_PSIZE_SHIFT);
    f.write(CR, cr);
    f.write(CR, cr | CR_STRT);
    f.advance_ns(1000);
    let (f, r) = run(f, SettingsSector::Six);
    assert_eq!(r, Ok(()));
    assert_eq!(f.erases.len(), 2);
    assert!(f.erases[1].start_ns >= f.erases[0].end_ns, "started after the first ended");
    assert_eq!(f.bus_errors, 0);
}

#[test]
fn the_settings_sectors_are_where_the_manual_puts_sectors_6_and_7() {
    // RM0383 §3.3 Table 4: sector 6 at 0x0804_0000, 7 at 0x0806_0000
    assert_eq!(SettingsSector::Six.offset(), 0x4_0000);
    assert_eq!(SettingsSector::Seven.offset(), 0x6_0000);
}

#[test]
fn the_lock_program_locks_after_a_program_that_stopped_early() {
    let mut cpu = Cpu(Flash::new(EraseTime::Typical));
    let program = erase_sector(SettingsSector::Seven);
    // stop after STRT, as a failed BSY wait would
    apply(&program[..7], &mut cpu).unwrap();
    apply(&fp::LOCK, &mut cpu).unwrap();
    assert_eq!(cpu.0.read(CR) & CR_LOCK, CR_LOCK);
    assert_eq!(cpu.0.read(SR) & SR_BSY, 0, "the lock waited for the erase to end");
}

#[test]
fn a_save_fits_the_watchdog_period_over_the_whole_lsi_range() {
    // worst case: the erase at its datasheet maximum, then every word of a
    // slot programmed at its maximum, then one 50 ms main-loop period
    // before the next pet; the erase pets the dog first (app/settings.rs)
    let (f, r) = run(Flash::new(EraseTime::Max), SettingsSector::Six);
    assert_eq!(r, Ok(()));
    let erase_us = (f.now_ns() / 1000) as u32;
    assert!(erase_us <= ERASE_MAX_US + 1000, "{erase_us} µs");
    let writes_us = (SLOT_LEN as u32 / 4) * WORD_PROGRAM_MAX_US;
    let save_us = erase_us + writes_us + 50_000;
    let shortest = period_us(WATCHDOG_US, LSI_MAX_HZ);
    assert!(save_us * 2 < shortest, "save {save_us} µs against the watchdog's {shortest} µs at 47 kHz");
}

/// `polyturn flash`'s sector layout (`polyturn_host::flash`) is the chip
/// model's, which is checked against RM0383 §3.3 Table 4 on its own.
#[test]
fn the_host_flashes_the_sectors_the_chip_model_has() {
    for (n, kib) in polyturn_host::flash::SECTOR_KIB.iter().enumerate() {
        assert_eq!(*kib, sector_kib(n as u32), "sector {n}");
    }
}
