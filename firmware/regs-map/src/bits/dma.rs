//! DMA bit fields (RM0383 §9.5).

/// DMA_SxCR (RM0383 §9.5.5).
pub mod dma_cr {
    use super::super::{bit, Field};
    pub const EN: Field = bit(0);
    pub const DMEIE: Field = bit(1);
    pub const TEIE: Field = bit(2);
    pub const HTIE: Field = bit(3);
    pub const TCIE: Field = bit(4);
    pub const PFCTRL: Field = bit(5);
    pub const DIR: Field = Field::new(6, 2);
    pub const CIRC: Field = bit(8);
    pub const PINC: Field = bit(9);
    pub const MINC: Field = bit(10);
    pub const PSIZE: Field = Field::new(11, 2);
    pub const MSIZE: Field = Field::new(13, 2);
    pub const PINCOS: Field = bit(15);
    pub const PL: Field = Field::new(16, 2);
    pub const DBM: Field = bit(18);
    pub const CT: Field = bit(19);
    pub const PBURST: Field = Field::new(21, 2);
    pub const MBURST: Field = Field::new(23, 2);
    pub const CHSEL: Field = Field::new(25, 3);
    /// DIR = 01: memory to peripheral
    pub const DIR_M2P: u32 = 0b01;
    pub const SIZE_HALF: u32 = 0b01;
    pub const SIZE_WORD: u32 = 0b10;
    /// PL = 11: very high priority
    pub const PL_VERY_HIGH: u32 = 0b11;
}

/// DMA_SxFCR (RM0383 §9.5.10) and DMA_SxNDTR (§9.5.6).
pub mod dma_fcr {
    use super::super::{bit, Field};
    pub const FTH: Field = Field::new(0, 2);
    pub const DMDIS: Field = bit(2);
    pub const FS: Field = Field::new(3, 3);
    pub const FEIE: Field = bit(7);
    pub const NDT: Field = Field::new(0, 16);
}

/// DMA_HISR / DMA_HIFCR (RM0383 §9.5.2, §9.5.4): stream 4..7 flags at 0, 6, 16, 22.
pub mod dma_isr {
    use super::super::{bit, Field};
    const fn base(stream: u32) -> u32 {
        [0, 6, 16, 22][(stream % 4) as usize]
    }
    pub const fn feif(stream: u32) -> Field {
        bit(base(stream))
    }
    pub const fn dmeif(stream: u32) -> Field {
        bit(base(stream) + 2)
    }
    pub const fn teif(stream: u32) -> Field {
        bit(base(stream) + 3)
    }
    pub const fn htif(stream: u32) -> Field {
        bit(base(stream) + 4)
    }
    pub const fn tcif(stream: u32) -> Field {
        bit(base(stream) + 5)
    }
}

/// DMA_HIFCR (RM0383 §9.5.4): stream 5's flag clears, at its flags' bits in HISR.
pub mod hifcr {
    use super::super::{bit, Field};
    pub const CFEIF5: Field = bit(6);
    /// CDMEIF5, CTEIF5, CHTIF5 and CTCIF5, bits 8 to 11
    pub const CDMEIF5_TO_CTCIF5: Field = Field::new(8, 4);
}
