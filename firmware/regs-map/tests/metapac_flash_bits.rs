//! The flash interface's FLASH_SR and FLASH_CR fields against ST's SVD as
//! stm32-metapac carries it: a wrong bit in the settings' erase is a failed
//! test, not a bricked settings sector.
use polyturn_regs::bits::{flash_cr, flash_sr};
use stm32_metapac::flash::regs::{Cr, Sr};
use stm32_metapac::flash::vals::Psize;

#[macro_use]
mod build_bits;

#[test]
fn the_flash_status_fields_match_metapac() {
    assert_eq!(bits!(Sr, |r| r.set_eop(true)), flash_sr::EOP.mask());
    assert_eq!(bits!(Sr, |r| r.set_operr(true)), flash_sr::OPERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_wrperr(true)), flash_sr::WRPERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_pgaerr(true)), flash_sr::PGAERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_pgperr(true)), flash_sr::PGPERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_pgserr(true)), flash_sr::PGSERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_bsy(true)), flash_sr::BSY.mask());
    // RDERR (bit 8, PCROP read error, RM0383 §3.8.4) is not in the SVD: it sits
    // in the gap after PGSERR
    assert_eq!(flash_sr::RDERR.mask(), flash_sr::PGSERR.mask() << 1);
}

#[test]
fn the_flash_control_fields_match_metapac() {
    assert_eq!(bits!(Cr, |r| r.set_pg(true)), flash_cr::PG.mask());
    assert_eq!(bits!(Cr, |r| r.set_ser(true)), flash_cr::SER.mask());
    assert_eq!(bits!(Cr, |r| r.set_mer(true)), flash_cr::MER.mask());
    assert_eq!(bits!(Cr, |r| r.set_snb(0xF)), flash_cr::SNB.mask());
    assert_eq!(bits!(Cr, |r| r.set_snb(7)), flash_cr::SNB.val(7));
    assert_eq!(bits!(Cr, |r| r.set_psize(Psize::PSIZE32)), flash_cr::PSIZE.val(flash_cr::PSIZE_X32));
    assert_eq!(bits!(Cr, |r| r.set_psize(Psize::from_bits(3))), flash_cr::PSIZE.mask());
    assert_eq!(bits!(Cr, |r| r.set_strt(true)), flash_cr::STRT.mask());
    assert_eq!(bits!(Cr, |r| r.set_eopie(true)), flash_cr::EOPIE.mask());
    assert_eq!(bits!(Cr, |r| r.set_lock(true)), flash_cr::LOCK.mask());
}
