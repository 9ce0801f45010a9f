//! Bit fields, one module per register, named as in RM0383 with its section. Every
//! field here is compared with `stm32-metapac`'s setters in `tests/metapac_*_bits.rs`.
//! Channels are numbered from 0 where a function takes one (`ccer::cce(0)` is CC1E); the
//! constants named after a channel (`ccer::CC1E`) are those functions' values.

/// A bit field: `width` bits starting at bit `shift`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    pub shift: u32,
    pub width: u32,
}

impl Field {
    pub const fn new(shift: u32, width: u32) -> Field {
        Field { shift, width }
    }
    /// The one-bit field at bit `shift`.
    pub const fn bit(shift: u32) -> Field {
        Field::new(shift, 1)
    }
    /// The field's bits in place.
    pub const fn mask(self) -> u32 {
        (((1u64 << self.width) - 1) as u32) << self.shift
    }
    /// The field's value in `reg`.
    pub const fn get(self, reg: u32) -> u32 {
        (reg & self.mask()) >> self.shift
    }
    /// `value` placed in the field. The value must fit: a wider one panics, at
    /// compile time where the word is a constant, so no word is ever built with
    /// a value cut short.
    pub const fn val(self, value: u32) -> u32 {
        assert!(value <= self.mask() >> self.shift, "value too wide for its field");
        value << self.shift
    }
    /// Whether a one-bit field is set in `reg`.
    pub const fn on(self, reg: u32) -> bool {
        reg & self.mask() != 0
    }
}

const fn bit(n: u32) -> Field {
    Field::bit(n)
}

/// TIMx_CR1 (RM0383 §12.4.1, §13.4.1, §14.5.1).
pub mod cr1 {
    use super::{bit, Field};
    pub const CEN: Field = bit(0);
    pub const UDIS: Field = bit(1);
    pub const URS: Field = bit(2);
    pub const OPM: Field = bit(3);
    pub const DIR: Field = bit(4);
    pub const CMS: Field = Field::new(5, 2);
    pub const ARPE: Field = bit(7);
    pub const CKD: Field = Field::new(8, 2);
}

/// TIMx_CR2 (RM0383 §12.4.2; MMS also §13.4.2).
pub mod cr2 {
    use super::{bit, Field};
    pub const CCPC: Field = bit(0);
    pub const CCUS: Field = bit(2);
    pub const CCDS: Field = bit(3);
    pub const MMS: Field = Field::new(4, 3);
    pub const TI1S: Field = bit(7);
    /// OISx (x = 1..4) at bit 8 + 2(x-1), OISxN one above.
    pub const fn ois(ch: u32) -> Field {
        bit(8 + 2 * ch)
    }
    pub const fn oisn(ch: u32) -> Field {
        bit(9 + 2 * ch)
    }
    /// MMS values (§12.4.2): reset, enable, update, compare pulse, OC1REF..OC4REF.
    pub const MMS_RESET: u32 = 0b000;
    pub const MMS_ENABLE: u32 = 0b001;
    pub const MMS_UPDATE: u32 = 0b010;
    pub const MMS_COMPARE_PULSE: u32 = 0b011;
    pub const MMS_OC1REF: u32 = 0b100;
    pub const MMS_OC2REF: u32 = 0b101;
}

/// TIMx_SMCR (RM0383 §13.4.3).
pub mod smcr {
    use super::{bit, Field};
    pub const SMS: Field = Field::new(0, 3);
    pub const TS: Field = Field::new(4, 3);
    pub const MSM: Field = bit(7);
    pub const ETF: Field = Field::new(8, 4);
    pub const ETPS: Field = Field::new(12, 2);
    pub const ECE: Field = bit(14);
    pub const ETP: Field = bit(15);
    pub const SMS_DISABLED: u32 = 0b000;
    /// §13.4.3: encoder mode 3, counting on both TI1FP1 and TI2FP2 edges
    pub const SMS_ENCODER_3: u32 = 0b011;
    pub const SMS_EXT_CLOCK_1: u32 = 0b111;
    pub const TS_ITR0: u32 = 0b000;
    pub const TS_ITR1: u32 = 0b001;
}

/// TIMx_DIER (RM0383 §12.4.4): interrupt enables at bits 0..7, DMA enables at 8..14.
pub mod dier {
    use super::{bit, Field};
    pub const UIE: Field = bit(0);
    pub const fn ccie(ch: u32) -> Field {
        bit(1 + ch)
    }
    pub const COMIE: Field = bit(5);
    pub const TIE: Field = bit(6);
    pub const BIE: Field = bit(7);
    pub const UDE: Field = bit(8);
    pub const fn ccde(ch: u32) -> Field {
        bit(9 + ch)
    }
    pub const COMDE: Field = bit(13);
    pub const TDE: Field = bit(14);
}

/// TIMx_SR (RM0383 §12.4.5), rc_w0 flags.
pub mod sr {
    use super::{bit, Field};
    pub const UIF: Field = bit(0);
    pub const fn ccif(ch: u32) -> Field {
        bit(1 + ch)
    }
    pub const COMIF: Field = bit(5);
    pub const TIF: Field = bit(6);
    pub const BIF: Field = bit(7);
    pub const fn ccof(ch: u32) -> Field {
        bit(9 + ch)
    }
    pub const CC1IF: Field = ccif(0);
    pub const CC3IF: Field = ccif(2);
    pub const CC1OF: Field = ccof(0);
    /// Every flag of a four-channel general-purpose timer (§13.4.5): UIF,
    /// CC1IF..CC4IF, TIF, CC1OF..CC4OF (TIM2..5 have no COMIF or BIF); writing 1 to
    /// one leaves it as it is.
    pub const GP_FLAGS: u32 = UIF.mask()
        | ccif(0).mask()
        | ccif(1).mask()
        | ccif(2).mask()
        | ccif(3).mask()
        | TIF.mask()
        | ccof(0).mask()
        | ccof(1).mask()
        | ccof(2).mask()
        | ccof(3).mask();
}

/// TIMx_EGR (RM0383 §12.4.6), write-only.
pub mod egr {
    use super::{bit, Field};
    pub const UG: Field = bit(0);
    pub const fn ccg(ch: u32) -> Field {
        bit(1 + ch)
    }
    pub const COMG: Field = bit(5);
    pub const TG: Field = bit(6);
    pub const BG: Field = bit(7);
}

/// TIMx_CCMR1 in output mode (RM0383 §12.4.7); `ch` is 0 for channel 1, 1 for channel 2.
pub mod ccmr {
    use super::{bit, Field};
    pub const fn ccs(ch: u32) -> Field {
        Field::new(8 * ch, 2)
    }
    pub const fn ocfe(ch: u32) -> Field {
        bit(2 + 8 * ch)
    }
    pub const fn ocpe(ch: u32) -> Field {
        bit(3 + 8 * ch)
    }
    pub const fn ocm(ch: u32) -> Field {
        Field::new(4 + 8 * ch, 3)
    }
    pub const fn occe(ch: u32) -> Field {
        bit(7 + 8 * ch)
    }
    /// CCMR1's channel 1 and 2 fields (CCMR2's channels 3 and 4 sit the same).
    pub const OC1PE: Field = ocpe(0);
    pub const OC1M: Field = ocm(0);
    pub const OC2PE: Field = ocpe(1);
    pub const OC2M: Field = ocm(1);
}

/// TIMx_CCMRx in input mode (RM0383 §13.4.7, §13.4.8); `ch` is 0 or 1 within the
/// register (CCMR2 holds channels 3 and 4). CCxS is the same field as in output mode.
pub mod ccmr_in {
    use super::{ccmr, Field};
    pub const fn icpsc(ch: u32) -> Field {
        Field::new(2 + 8 * ch, 2)
    }
    pub const fn icf(ch: u32) -> Field {
        Field::new(4 + 8 * ch, 4)
    }
    /// CCxS values: 00 output, 01 ICx on its own TIx, 10 on the other TI of the pair,
    /// 11 on TRC ("working only if an internal trigger input is selected through TS")
    pub const CCS_OUTPUT: u32 = 0b00;
    pub const CCS_TI: u32 = 0b01;
    pub const CCS_TI_OTHER: u32 = 0b10;
    pub const CCS_TRC: u32 = 0b11;
    /// ICxF = 0011: f_SAMPLING = f_CK_INT, N = 8
    pub const ICF_CK_INT_N8: u32 = 0b0011;
    /// CCMR1's channel 1 and 2 fields (CCMR2's CC3S, IC3PSC, IC3F sit where CC1S,
    /// IC1PSC, IC1F do, CC4S, IC4F where CC2S, IC2F do).
    pub const CC1S: Field = ccmr::ccs(0);
    pub const IC1PSC: Field = icpsc(0);
    pub const IC1F: Field = icf(0);
    pub const CC2S: Field = ccmr::ccs(1);
    pub const IC2F: Field = icf(1);
}

/// OCxM values (RM0383 §12.4.7).
pub mod ocm {
    pub const FROZEN: u32 = 0b000;
    pub const ACTIVE_ON_MATCH: u32 = 0b001;
    pub const INACTIVE_ON_MATCH: u32 = 0b010;
    pub const TOGGLE: u32 = 0b011;
    pub const FORCE_INACTIVE: u32 = 0b100;
    pub const FORCE_ACTIVE: u32 = 0b101;
    pub const PWM1: u32 = 0b110;
    pub const PWM2: u32 = 0b111;
}

/// TIMx_CCER (RM0383 §12.4.9); `ch` is 0-based.
pub mod ccer {
    use super::{bit, Field};
    pub const fn cce(ch: u32) -> Field {
        bit(4 * ch)
    }
    pub const fn ccp(ch: u32) -> Field {
        bit(1 + 4 * ch)
    }
    pub const fn ccne(ch: u32) -> Field {
        bit(2 + 4 * ch)
    }
    pub const fn ccnp(ch: u32) -> Field {
        bit(3 + 4 * ch)
    }
    pub const CC1E: Field = cce(0);
    pub const CC2E: Field = cce(1);
    pub const CC3E: Field = cce(2);
}

/// TIMx_BDTR (RM0383 §12.4.18).
pub mod bdtr {
    use super::{bit, Field};
    pub const DTG: Field = Field::new(0, 8);
    pub const LOCK: Field = Field::new(8, 2);
    pub const OSSI: Field = bit(10);
    pub const OSSR: Field = bit(11);
    pub const BKE: Field = bit(12);
    pub const BKP: Field = bit(13);
    pub const AOE: Field = bit(14);
    pub const MOE: Field = bit(15);
}

/// TIMx_DCR (RM0383 §12.4.19) and TIMx_RCR (§12.4.13).
pub mod dcr {
    use super::Field;
    pub const DBA: Field = Field::new(0, 5);
    pub const DBL: Field = Field::new(8, 5);
    pub const REP: Field = Field::new(0, 8);
}

mod dma;
mod flash;
pub use dma::{dma_cr, dma_fcr, dma_isr, hifcr};
pub use flash::{flash_cr, flash_keyr, flash_sr};

/// CRC_CR (RM0383 §4.4.3).
pub mod crc_cr {
    use super::{bit, Field};
    /// DR back to 0xFFFF_FFFF; cleared by hardware
    pub const RESET: Field = bit(0);
}

/// RCC_AHB1ENR (RM0383 §6.3.9): the clock enables of the ports and the CRC unit.
pub mod rcc_ahb1enr {
    use super::{bit, Field};
    pub const GPIOAEN: Field = bit(0);
    pub const GPIOBEN: Field = bit(1);
    pub const GPIOCEN: Field = bit(2);
    pub const CRCEN: Field = bit(12);
}
