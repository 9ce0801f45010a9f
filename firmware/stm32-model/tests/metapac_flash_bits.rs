//! The firmware's FLASH_SR and FLASH_CR fields (`regs::fields`, which its
//! sector-erase program is written in) against ST's SVD as stm32-metapac
//! carries it: a wrong bit in the erase is a failed test, not a bricked
//! settings sector. (The timer and DMA fields are checked through the
//! model's table, `tests/register_fields.rs` at the workspace root.)
use polyturn_firmware::regs::fields::{flash_cr, flash_sr};
use stm32_metapac::flash::regs::{Cr, Sr};
use stm32_metapac::flash::vals::Psize;

#[macro_use]
mod build_bits;

#[test]
fn the_flash_fields_the_erase_writes_are_the_svds() {
    assert_eq!(bits!(Sr, |r| r.set_eop(true)), flash_sr::EOP.mask());
    assert_eq!(bits!(Sr, |r| r.set_operr(true)), flash_sr::OPERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_wrperr(true)), flash_sr::WRPERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_pgaerr(true)), flash_sr::PGAERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_pgperr(true)), flash_sr::PGPERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_pgserr(true)), flash_sr::PGSERR.mask());
    assert_eq!(bits!(Sr, |r| r.set_bsy(true)), flash_sr::BSY.mask());
    assert_eq!(bits!(Cr, |r| r.set_ser(true)), flash_cr::SER.mask());
    assert_eq!(bits!(Cr, |r| r.set_snb(0xF)), flash_cr::SNB.mask());
    assert_eq!(bits!(Cr, |r| r.set_snb(7)), flash_cr::SNB.val(7));
    assert_eq!(bits!(Cr, |r| r.set_psize(Psize::PSIZE32)), flash_cr::PSIZE.val(flash_cr::PSIZE_X32));
    assert_eq!(bits!(Cr, |r| r.set_strt(true)), flash_cr::STRT.mask());
    assert_eq!(bits!(Cr, |r| r.set_lock(true)), flash_cr::LOCK.mask());
}
