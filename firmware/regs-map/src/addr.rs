//! Register addresses.
//!
//! Peripheral base addresses: RM0383 §2.3 "Memory map" (Table 1, register boundary
//! addresses). Register offsets: the register map at the end of each register chapter
//! (RM0383 §12.4.21 TIM1, §13.4.21 TIM2..5, §14.4.13 TIM9, §14.5.12 TIM10/11, §9.5.11
//! DMA, §8.4.11 GPIO, §3.8.7 flash interface), each register's own section by its
//! offset. All of them are checked against `stm32-metapac` in `tests/metapac_addr.rs`.

/// The main flash memory: 512 KiB at 0x0800_0000 (RM0383 §2.3 Table 1,
/// §3.3 Table 4: sectors 0-7 of the STM32F411xE).
pub const FLASH_BASE: u32 = 0x0800_0000;
/// Size of the STM32F411xE's main flash in bytes (RM0383 §3.3 Table 4).
pub const FLASH_SIZE: u32 = 512 * 1024;

/// SRAM1: 128 KiB at 0x2000_0000 (RM0383 §2.3, §2.3.1 "Embedded SRAM").
pub const SRAM_BASE: u32 = 0x2000_0000;
/// Size of the STM32F411xC/E SRAM in bytes (RM0383 §2.3.1).
pub const SRAM_SIZE: u32 = 128 * 1024;

/// TIM2 base (APB1), RM0383 §2.3 Table 1.
pub const TIM2: u32 = 0x4000_0000;
/// TIM3 base (APB1), RM0383 §2.3 Table 1.
pub const TIM3: u32 = 0x4000_0400;
/// TIM4 base (APB1), RM0383 §2.3 Table 1.
pub const TIM4: u32 = 0x4000_0800;
/// TIM5 base (APB1), RM0383 §2.3 Table 1.
pub const TIM5: u32 = 0x4000_0C00;
/// TIM1 base (APB2), RM0383 §2.3 Table 1.
pub const TIM1: u32 = 0x4001_0000;
/// TIM9 base (APB2), RM0383 §2.3 Table 1.
pub const TIM9: u32 = 0x4001_4000;
/// TIM10 base (APB2), RM0383 §2.3 Table 1.
pub const TIM10: u32 = 0x4001_4400;
/// TIM11 base (APB2), RM0383 §2.3 Table 1.
pub const TIM11: u32 = 0x4001_4800;
/// GPIOA base (AHB1), RM0383 §2.3 Table 1.
pub const GPIOA: u32 = 0x4002_0000;
/// GPIOB base (AHB1), RM0383 §2.3 Table 1.
pub const GPIOB: u32 = 0x4002_0400;
/// GPIOC base (AHB1), RM0383 §2.3 Table 1.
pub const GPIOC: u32 = 0x4002_0800;
/// CRC calculation unit base (AHB1), RM0383 §2.3 Table 1.
pub const CRC: u32 = 0x4002_3000;
/// RCC base (AHB1), RM0383 §2.3 Table 1.
pub const RCC: u32 = 0x4002_3800;
/// Flash interface registers' base (AHB1), RM0383 §2.3 Table 1.
pub const FLASH_R: u32 = 0x4002_3C00;
/// DMA2 base (AHB1), RM0383 §2.3 Table 1.
pub const DMA2: u32 = 0x4002_6400;
/// Every peripheral above decodes a 1 KiB window (RM0383 §2.3 Table 1 boundaries).
pub const PERIPH_WINDOW: u32 = 0x400;

/// Register offsets shared by the timers (RM0383 §12.4.21, §13.4.21, §14.4.13,
/// §14.5.12): TIM1's sections; a timer without a register leaves its offset free.
pub mod off {
    /// TIMx_CR1 (§12.4.1)
    pub const CR1: u32 = 0x00;
    /// TIMx_CR2 (§12.4.2)
    pub const CR2: u32 = 0x04;
    /// TIMx_SMCR (§12.4.3)
    pub const SMCR: u32 = 0x08;
    /// TIMx_DIER (§12.4.4)
    pub const DIER: u32 = 0x0C;
    /// TIMx_SR (§12.4.5)
    pub const SR: u32 = 0x10;
    /// TIMx_EGR (§12.4.6)
    pub const EGR: u32 = 0x14;
    /// TIMx_CCMR1 (§12.4.7)
    pub const CCMR1: u32 = 0x18;
    /// TIMx_CCMR2 (§12.4.8)
    pub const CCMR2: u32 = 0x1C;
    /// TIMx_CCER (§12.4.9)
    pub const CCER: u32 = 0x20;
    /// TIMx_CNT (§12.4.10)
    pub const CNT: u32 = 0x24;
    /// TIMx_PSC (§12.4.11)
    pub const PSC: u32 = 0x28;
    /// TIMx_ARR (§12.4.12)
    pub const ARR: u32 = 0x2C;
    /// TIMx_RCR, TIM1 only (§12.4.13).
    pub const RCR: u32 = 0x30;
    /// TIMx_CCR1..CCR4 (§12.4.14..§12.4.17)
    pub const CCR1: u32 = 0x34;
    pub const CCR2: u32 = 0x38;
    pub const CCR3: u32 = 0x3C;
    pub const CCR4: u32 = 0x40;
    /// TIMx_BDTR, TIM1 only (§12.4.18).
    pub const BDTR: u32 = 0x44;
    /// TIMx_DCR (§12.4.19)
    pub const DCR: u32 = 0x48;
    /// TIMx_DMAR (§12.4.20)
    pub const DMAR: u32 = 0x4C;
    /// TIM2/TIM5/TIM11 option register (§13.4.19, §14.5.11).
    pub const OR: u32 = 0x50;
}

pub const TIM1_CR1: u32 = TIM1 + off::CR1;
pub const TIM1_CR2: u32 = TIM1 + off::CR2;
pub const TIM1_SMCR: u32 = TIM1 + off::SMCR;
pub const TIM1_DIER: u32 = TIM1 + off::DIER;
pub const TIM1_SR: u32 = TIM1 + off::SR;
pub const TIM1_EGR: u32 = TIM1 + off::EGR;
pub const TIM1_CCMR1: u32 = TIM1 + off::CCMR1;
pub const TIM1_CCMR2: u32 = TIM1 + off::CCMR2;
pub const TIM1_CCER: u32 = TIM1 + off::CCER;
pub const TIM1_CNT: u32 = TIM1 + off::CNT;
pub const TIM1_PSC: u32 = TIM1 + off::PSC;
pub const TIM1_ARR: u32 = TIM1 + off::ARR;
pub const TIM1_RCR: u32 = TIM1 + off::RCR;
pub const TIM1_CCR1: u32 = TIM1 + off::CCR1;
pub const TIM1_CCR2: u32 = TIM1 + off::CCR2;
pub const TIM1_CCR3: u32 = TIM1 + off::CCR3;
pub const TIM1_CCR4: u32 = TIM1 + off::CCR4;
pub const TIM1_BDTR: u32 = TIM1 + off::BDTR;
pub const TIM1_DCR: u32 = TIM1 + off::DCR;
pub const TIM1_DMAR: u32 = TIM1 + off::DMAR;

pub const TIM2_CR1: u32 = TIM2 + off::CR1;
pub const TIM2_CR2: u32 = TIM2 + off::CR2;
pub const TIM2_SMCR: u32 = TIM2 + off::SMCR;
pub const TIM2_DIER: u32 = TIM2 + off::DIER;
pub const TIM2_SR: u32 = TIM2 + off::SR;
pub const TIM2_EGR: u32 = TIM2 + off::EGR;
pub const TIM2_CNT: u32 = TIM2 + off::CNT;
pub const TIM2_PSC: u32 = TIM2 + off::PSC;
pub const TIM2_ARR: u32 = TIM2 + off::ARR;

// TIM9 (RM0383 §14.4.13 register map: the TIM1 offsets, no CR2, RCR, CCR3/4, BDTR, DCR).
pub const TIM9_CR1: u32 = TIM9 + off::CR1;
pub const TIM9_SMCR: u32 = TIM9 + off::SMCR;
pub const TIM9_DIER: u32 = TIM9 + off::DIER;
pub const TIM9_SR: u32 = TIM9 + off::SR;
pub const TIM9_EGR: u32 = TIM9 + off::EGR;
pub const TIM9_CCMR1: u32 = TIM9 + off::CCMR1;
pub const TIM9_CCER: u32 = TIM9 + off::CCER;
pub const TIM9_CNT: u32 = TIM9 + off::CNT;
pub const TIM9_PSC: u32 = TIM9 + off::PSC;
pub const TIM9_ARR: u32 = TIM9 + off::ARR;
pub const TIM9_CCR1: u32 = TIM9 + off::CCR1;
pub const TIM9_CCR2: u32 = TIM9 + off::CCR2;

pub const TIM11_CR1: u32 = TIM11 + off::CR1;
pub const TIM11_DIER: u32 = TIM11 + off::DIER;
pub const TIM11_SR: u32 = TIM11 + off::SR;
pub const TIM11_EGR: u32 = TIM11 + off::EGR;
pub const TIM11_CNT: u32 = TIM11 + off::CNT;
pub const TIM11_PSC: u32 = TIM11 + off::PSC;
pub const TIM11_ARR: u32 = TIM11 + off::ARR;

/// DMA register offsets (RM0383 §9.5.1-§9.5.10): stream x registers at 0x10 + 0x18·x.
pub mod dma_off {
    /// DMA_LISR (§9.5.1)
    pub const LISR: u32 = 0x00;
    /// DMA_HISR (§9.5.2)
    pub const HISR: u32 = 0x04;
    /// DMA_LIFCR (§9.5.3)
    pub const LIFCR: u32 = 0x08;
    /// DMA_HIFCR (§9.5.4)
    pub const HIFCR: u32 = 0x0C;
    /// DMA_SxCR (§9.5.5)
    pub const fn sxcr(x: u32) -> u32 {
        0x10 + 0x18 * x
    }
    /// DMA_SxNDTR (§9.5.6)
    pub const fn sxndtr(x: u32) -> u32 {
        0x14 + 0x18 * x
    }
    /// DMA_SxPAR (§9.5.7)
    pub const fn sxpar(x: u32) -> u32 {
        0x18 + 0x18 * x
    }
    /// DMA_SxM0AR (§9.5.8)
    pub const fn sxm0ar(x: u32) -> u32 {
        0x1C + 0x18 * x
    }
    /// DMA_SxM1AR (§9.5.9)
    pub const fn sxm1ar(x: u32) -> u32 {
        0x20 + 0x18 * x
    }
    /// DMA_SxFCR (§9.5.10)
    pub const fn sxfcr(x: u32) -> u32 {
        0x24 + 0x18 * x
    }
}

pub const DMA2_LISR: u32 = DMA2 + dma_off::LISR;
pub const DMA2_HISR: u32 = DMA2 + dma_off::HISR;
pub const DMA2_LIFCR: u32 = DMA2 + dma_off::LIFCR;
pub const DMA2_HIFCR: u32 = DMA2 + dma_off::HIFCR;
pub const DMA2_S5CR: u32 = DMA2 + dma_off::sxcr(5);
pub const DMA2_S5NDTR: u32 = DMA2 + dma_off::sxndtr(5);
pub const DMA2_S5PAR: u32 = DMA2 + dma_off::sxpar(5);
pub const DMA2_S5M0AR: u32 = DMA2 + dma_off::sxm0ar(5);
pub const DMA2_S5M1AR: u32 = DMA2 + dma_off::sxm1ar(5);
pub const DMA2_S5FCR: u32 = DMA2 + dma_off::sxfcr(5);

/// GPIO register offsets (RM0383 §8.4.11 register map).
pub mod gpio_off {
    /// GPIOx_MODER (§8.4.1)
    pub const MODER: u32 = 0x00;
    /// GPIOx_OTYPER (§8.4.2)
    pub const OTYPER: u32 = 0x04;
    /// GPIOx_OSPEEDR (§8.4.3)
    pub const OSPEEDR: u32 = 0x08;
    /// GPIOx_PUPDR (§8.4.4)
    pub const PUPDR: u32 = 0x0C;
    /// GPIOx_IDR (§8.4.5)
    pub const IDR: u32 = 0x10;
    /// GPIOx_ODR (§8.4.6)
    pub const ODR: u32 = 0x14;
    /// GPIOx_BSRR (§8.4.7)
    pub const BSRR: u32 = 0x18;
    /// GPIOx_LCKR (§8.4.8)
    pub const LCKR: u32 = 0x1C;
    /// GPIOx_AFRL, GPIOx_AFRH (§8.4.9, §8.4.10)
    pub const AFRL: u32 = 0x20;
    pub const AFRH: u32 = 0x24;
}

pub const GPIOA_IDR: u32 = GPIOA + gpio_off::IDR;
pub const GPIOA_BSRR: u32 = GPIOA + gpio_off::BSRR;
pub const GPIOB_IDR: u32 = GPIOB + gpio_off::IDR;

/// CRC unit register offsets (RM0383 §4.4.4 register map).
pub mod crc_off {
    /// CRC_DR (§4.4.1)
    pub const DR: u32 = 0x00;
    /// CRC_IDR (§4.4.2)
    pub const IDR: u32 = 0x04;
    /// CRC_CR (§4.4.3)
    pub const CR: u32 = 0x08;
}

pub const CRC_DR: u32 = CRC + crc_off::DR;
pub const CRC_CR: u32 = CRC + crc_off::CR;

/// RCC_AHB1ENR (RM0383 §6.3.9: offset 0x30).
pub const RCC_AHB1ENR: u32 = RCC + 0x30;

/// Flash interface register offsets (RM0383 §3.8.7 register map).
pub mod flash_off {
    /// FLASH_KEYR (§3.8.2)
    pub const KEYR: u32 = 0x04;
    /// FLASH_SR (§3.8.4)
    pub const SR: u32 = 0x0C;
    /// FLASH_CR (§3.8.5)
    pub const CR: u32 = 0x10;
}

pub const FLASH_KEYR: u32 = FLASH_R + flash_off::KEYR;
pub const FLASH_SR: u32 = FLASH_R + flash_off::SR;
pub const FLASH_CR: u32 = FLASH_R + flash_off::CR;
