//! The register fields the register programs write, by name: the timer
//! fields of RM0383 §12.4 (TIM1; TIM9's are the same bits, §14.4) and
//! DMA_SxCR (§9.5.5). `tests/register_fields.rs` checks every one against
//! the model's field table, which the model's own tests check against ST's
//! SVD (stm32-metapac): the words the MCU writes are spelt in the same
//! names as the manual, and a wrong bit fails a test, not a board.

/// A field of `width` bits at `shift`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    pub shift: u32,
    pub width: u32,
}

impl Field {
    pub const fn new(shift: u32, width: u32) -> Field {
        Field { shift, width }
    }
    pub const fn bit(shift: u32) -> Field {
        Field::new(shift, 1)
    }
    pub const fn mask(self) -> u32 {
        (u32::MAX >> (32 - self.width)) << self.shift
    }
    /// `value` in this field (the value must fit: checked at compile time
    /// where the words are constants)
    pub const fn val(self, value: u32) -> u32 {
        assert!(value <= self.mask() >> self.shift, "value too wide for its field");
        value << self.shift
    }
}

/// TIMx_CR1 (§12.4.1)
pub mod cr1 {
    use super::Field;
    pub const CEN: Field = Field::bit(0);
    pub const URS: Field = Field::bit(2);
    pub const OPM: Field = Field::bit(3);
    pub const ARPE: Field = Field::bit(7);
}

/// TIMx_CR2 (§12.4.2, §13.4.2): MMS = 100, OC1REF is TRGO; 011, the compare
/// pulse, TRGO pulses at each CC1 capture or match
pub mod cr2 {
    use super::Field;
    pub const MMS: Field = Field::new(4, 3);
    pub const MMS_COMPARE_PULSE: u32 = 0b011;
    pub const MMS_OC1REF: u32 = 0b100;
}

/// TIMx_SMCR (§13.4.3): SMS = 111 external clock mode 1, 011 encoder mode
/// 3, 000 slave mode off; TS = 000 ITR0, 001 ITR1
pub mod smcr {
    use super::Field;
    pub const SMS: Field = Field::new(0, 3);
    pub const TS: Field = Field::new(4, 3);
    pub const SMS_ENCODER_3: u32 = 0b011;
    pub const SMS_EXT_CLOCK_1: u32 = 0b111;
    pub const TS_ITR1: u32 = 0b001;
}

/// TIMx_DIER (§12.4.4)
pub mod dier {
    use super::Field;
    pub const UIE: Field = Field::bit(0);
    pub const UDE: Field = Field::bit(8);
}

/// TIMx_SR (§12.4.5, §13.4.5): rc_w0 flags
pub mod sr {
    use super::Field;
    pub const UIF: Field = Field::bit(0);
    pub const CC1IF: Field = Field::bit(1);
    pub const CC3IF: Field = Field::bit(3);
    pub const CC1OF: Field = Field::bit(9);
    /// every flag of a four-channel general-purpose timer (§13.4.5): UIF,
    /// CC1IF..CC4IF, TIF, CC1OF..CC4OF; writing 1 to one leaves it as it is
    pub const GP_FLAGS: u32 = 0x1E5F;
}

/// TIMx_EGR (§12.4.6)
pub mod egr {
    use super::Field;
    pub const UG: Field = Field::bit(0);
}

/// TIMx_CCMR1, output mode (§12.4.7): OCxM and the CCRx preloads
pub mod ccmr1 {
    use super::Field;
    pub const OC1PE: Field = Field::bit(3);
    pub const OC1M: Field = Field::new(4, 3);
    pub const OC2PE: Field = Field::bit(11);
    pub const OC2M: Field = Field::new(12, 3);
    pub const TOGGLE: u32 = 0b011;
    pub const FORCE_INACTIVE: u32 = 0b100;
    pub const PWM1: u32 = 0b110;
    pub const PWM2: u32 = 0b111;
}

/// TIMx_CCMR1/CCMR2 in input mode (§13.4.7, §13.4.8): CCMR2's CC3S, IC3F
/// are CC1S, IC1F's bits, CC4S, IC4F CC2S, IC2F's
pub mod ccmr_in {
    use super::Field;
    pub const CC1S: Field = Field::new(0, 2);
    pub const IC1PSC: Field = Field::new(2, 2);
    pub const IC1F: Field = Field::new(4, 4);
    pub const CC2S: Field = Field::new(8, 2);
    pub const IC2F: Field = Field::new(12, 4);
    /// CCxS = 01: ICx on TIx; 11: ICx on TRC
    pub const CCS_TI: u32 = 0b01;
    pub const CCS_TRC: u32 = 0b11;
    /// ICxF = 0011: 8 samples at f_CK_INT
    pub const ICF_CK_INT_N8: u32 = 0b0011;
}

/// TIMx_CCER (§12.4.9, §13.4.9): outputs enabled, active high; an input's
/// capture enabled, on the rising edge (CCxP = CCxNP = 0)
pub mod ccer {
    use super::Field;
    pub const CC1E: Field = Field::bit(0);
    pub const CC2E: Field = Field::bit(4);
    pub const CC3E: Field = Field::bit(8);
}

/// TIMx_BDTR (§12.4.18): an advanced timer's outputs need MOE
pub mod bdtr {
    use super::Field;
    pub const MOE: Field = Field::bit(15);
}

/// TIMx_DCR (§12.4.19): the burst's first register and its length − 1
pub mod dcr {
    use super::Field;
    pub const DBA: Field = Field::new(0, 5);
    pub const DBL: Field = Field::new(8, 5);
}

/// DMA_SxCR (§9.5.5)
pub mod dma_cr {
    use super::Field;
    pub const EN: Field = Field::bit(0);
    pub const DIR: Field = Field::new(6, 2);
    pub const CIRC: Field = Field::bit(8);
    pub const MINC: Field = Field::bit(10);
    pub const PSIZE: Field = Field::new(11, 2);
    pub const MSIZE: Field = Field::new(13, 2);
    pub const PL: Field = Field::new(16, 2);
    pub const CHSEL: Field = Field::new(25, 3);
    pub const DIR_M2P: u32 = 0b01;
    pub const SIZE_WORD: u32 = 0b10;
    pub const PL_VERY_HIGH: u32 = 0b11;
}

/// DMA_HIFCR (§9.5.4): stream 5's flag clears, CFEIF5 and CDMEIF5 to CTCIF5
pub mod hifcr {
    use super::Field;
    pub const CFEIF5: Field = Field::bit(6);
    pub const CDMEIF5_TO_CTCIF5: Field = Field::new(8, 4);
}

/// FLASH_SR (§3.8.4): end of operation, the error flags, busy
pub mod flash_sr {
    use super::Field;
    pub const EOP: Field = Field::bit(0);
    pub const OPERR: Field = Field::bit(1);
    pub const WRPERR: Field = Field::bit(4);
    pub const PGAERR: Field = Field::bit(5);
    pub const PGPERR: Field = Field::bit(6);
    pub const PGSERR: Field = Field::bit(7);
    /// PCROP read error (RM0383 §3.8.4; not in the SVD the tests check against)
    pub const RDERR: Field = Field::bit(8);
    pub const BSY: Field = Field::bit(16);
}

/// FLASH_CR (§3.8.5): sector erase, its sector, the program size, start, lock
pub mod flash_cr {
    use super::Field;
    pub const SER: Field = Field::bit(1);
    pub const SNB: Field = Field::new(3, 4);
    pub const PSIZE: Field = Field::new(8, 2);
    pub const PSIZE_X32: u32 = 0b10;
    pub const STRT: Field = Field::bit(16);
    pub const LOCK: Field = Field::bit(31);
}
