//! The flash interface model, one test per statement of RM0383 §3.5/§3.8
//! (and DS10314's erase times).
use polyturn_stm32_model::flash::*;

const MS: u64 = 1_000_000;

fn unlocked() -> Flash {
    let mut f = Flash::new(EraseTime::Typical);
    f.write(KEYR, KEY1);
    f.write(KEYR, KEY2);
    f
}

fn erase(f: &mut Flash, sector: u32, psize: u32) {
    let cr = CR_SER | (sector << CR_SNB_SHIFT) | (psize << CR_PSIZE_SHIFT);
    f.write(CR, cr);
    f.write(CR, cr | CR_STRT);
}

#[test]
fn flash_cr_is_locked_at_reset_and_ignores_writes_until_unlocked() {
    // §3.5.1, §3.8.5 (reset value 0x8000_0000)
    let mut f = Flash::new(EraseTime::Typical);
    assert_eq!(f.read(CR), CR_LOCK);
    erase(&mut f, 6, 2);
    assert!(f.erases.is_empty());
    assert_eq!(f.read(CR), CR_LOCK);
}

#[test]
fn key1_then_key2_unlocks_and_setting_lock_locks_again() {
    let mut f = unlocked();
    assert_eq!(f.read(CR) & CR_LOCK, 0);
    f.write(CR, CR_LOCK);
    assert_eq!(f.read(CR) & CR_LOCK, CR_LOCK);
    assert_eq!(f.bus_errors, 0);
}

#[test]
fn a_wrong_key_sequence_is_a_bus_error_and_locks_until_reset() {
    // §3.5.1 "any wrong sequence will return a bus error and lock up the
    // FLASH_CR register until the next reset"
    let mut f = Flash::new(EraseTime::Typical);
    f.write(KEYR, KEY2);
    assert_eq!(f.bus_errors, 1);
    f.write(KEYR, KEY1);
    f.write(KEYR, KEY2);
    assert_ne!(f.read(CR) & CR_LOCK, 0, "still locked until reset");
}

#[test]
fn keys_written_to_an_unlocked_register_are_a_wrong_sequence() {
    let mut f = unlocked();
    f.write(KEYR, KEY1);
    assert_eq!(f.bus_errors, 1);
    assert_ne!(f.read(CR) & CR_LOCK, 0);
}

#[test]
fn a_sector_erase_keeps_bsy_for_the_datasheet_time_of_its_parallelism() {
    // §3.5.3 sequence; §3.5.2 erase time by PSIZE; DS10314 t_ERASE128KB
    for (psize, typ_ms) in [(0, 2000), (1, 1300), (2, 1000)] {
        let mut f = unlocked();
        erase(&mut f, 6, psize);
        assert_ne!(f.read(SR) & SR_BSY, 0);
        f.advance_ns(typ_ms * MS - 1);
        assert_ne!(f.read(SR) & SR_BSY, 0, "×{} still busy", 8 << psize);
        f.advance_ns(1);
        assert_eq!(f.read(SR) & SR_BSY, 0);
        assert_eq!(f.erases, vec![Erase { sector: 6, psize, start_ns: 0, end_ns: typ_ms * MS }]);
    }
}

#[test]
fn the_worst_case_erase_times_are_twice_the_typical() {
    let mut f = Flash::new(EraseTime::Max);
    f.write(KEYR, KEY1);
    f.write(KEYR, KEY2);
    erase(&mut f, 7, 2);
    assert_eq!(f.erases[0].end_ns, 2000 * MS);
    assert_eq!(sector_kib(3), 16);
    assert_eq!(sector_kib(4), 64);
    assert_eq!(sector_kib(5), 128);
}

#[test]
fn strt_clears_with_bsy_and_eop_is_set_only_with_eopie() {
    // §3.8.5 STRT "cleared when the BSY bit is cleared"; §3.8.4 EOP
    let mut f = unlocked();
    erase(&mut f, 5, 2);
    f.advance_ns(1000 * MS);
    assert_eq!(f.read(CR) & CR_STRT, 0);
    assert_eq!(f.read(SR) & SR_EOP, 0);
    let cr = CR_SER | (5 << CR_SNB_SHIFT) | (2 << CR_PSIZE_SHIFT) | CR_EOPIE;
    f.write(CR, cr);
    f.write(CR, cr | CR_STRT);
    f.advance_ns(1000 * MS);
    assert_ne!(f.read(SR) & SR_EOP, 0);
    f.write(SR, SR_EOP);
    assert_eq!(f.read(SR) & SR_EOP, 0, "rc_w1");
}

#[test]
fn a_flash_cr_write_while_busy_waits_for_the_end_of_the_operation() {
    // §3.5.1 note: the AHB bus stalls until BSY is cleared
    let mut f = unlocked();
    erase(&mut f, 6, 2);
    f.advance_ns(10 * MS);
    f.write(CR, CR_LOCK);
    assert_eq!(f.now_ns(), 1000 * MS);
    assert_eq!(f.read(CR), CR_LOCK);
}

#[test]
fn strt_without_ser_starts_nothing() {
    let mut f = unlocked();
    f.write(CR, 2 << CR_PSIZE_SHIFT | CR_STRT);
    assert!(f.erases.is_empty());
    assert_eq!(f.read(SR) & SR_BSY, 0);
}
