//! The fields of the image's boot check (the CRC unit's reset, the clock
//! enables of the CRC unit and the LEDs' ports) against ST's SVD as
//! stm32-metapac carries it.
use polyturn_regs::bits::{crc_cr, rcc_ahb1enr};
use stm32_metapac::crc::regs::Cr;
use stm32_metapac::rcc::regs::Ahb1enr;

#[macro_use]
mod build_bits;

#[test]
fn the_crc_and_clock_enable_fields_match_metapac() {
    assert_eq!(bits!(Cr, |r| r.set_reset(true)), crc_cr::RESET.mask());
    assert_eq!(bits!(Ahb1enr, |r| r.set_gpioaen(true)), rcc_ahb1enr::GPIOAEN.mask());
    assert_eq!(bits!(Ahb1enr, |r| r.set_gpioben(true)), rcc_ahb1enr::GPIOBEN.mask());
    assert_eq!(bits!(Ahb1enr, |r| r.set_gpiocen(true)), rcc_ahb1enr::GPIOCEN.mask());
    assert_eq!(bits!(Ahb1enr, |r| r.set_crcen(true)), rcc_ahb1enr::CRCEN.mask());
}
