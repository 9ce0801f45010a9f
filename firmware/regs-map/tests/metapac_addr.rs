//! Every address in `addr` checked against `stm32-metapac` (ST's SVD data as
//! curated by the embassy project), so that none of them rests on a hand
//! reading of the manual alone; and the rest of ST's map the register
//! programs rely on: the DMA request, the pins and the vector.
use polyturn_regs::addr::*;
use stm32_metapac as pac;

fn a<T>(p: *mut T) -> u32 {
    p as usize as u32
}

#[test]
fn base_addresses_and_sram_match_metapac() {
    let bases = [
        (a(pac::TIM1.as_ptr()), TIM1),
        (a(pac::TIM2.as_ptr()), TIM2),
        (a(pac::TIM3.as_ptr()), TIM3),
        (a(pac::TIM4.as_ptr()), TIM4),
        (a(pac::TIM5.as_ptr()), TIM5),
        (a(pac::TIM9.as_ptr()), TIM9),
        (a(pac::TIM10.as_ptr()), TIM10),
        (a(pac::TIM11.as_ptr()), TIM11),
        (a(pac::GPIOA.as_ptr()), GPIOA),
        (a(pac::GPIOB.as_ptr()), GPIOB),
        (a(pac::GPIOC.as_ptr()), GPIOC),
        (a(pac::CRC.as_ptr()), CRC),
        (a(pac::RCC.as_ptr()), RCC),
        (a(pac::FLASH.as_ptr()), FLASH_R),
        (a(pac::DMA2.as_ptr()), DMA2),
    ];
    for (pac_addr, ours) in bases {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
    let sram = pac::metadata::METADATA.memory[0].iter().find(|r| r.name == "SRAM").unwrap();
    assert_eq!((sram.address, sram.size), (SRAM_BASE, SRAM_SIZE));
}

#[test]
fn timer_register_addresses_match_metapac() {
    let t = pac::TIM1;
    let tim1 = [
        (a(t.cr1().as_ptr()), TIM1_CR1),
        (a(t.cr2().as_ptr()), TIM1_CR2),
        (a(t.smcr().as_ptr()), TIM1_SMCR),
        (a(t.dier().as_ptr()), TIM1_DIER),
        (a(t.sr().as_ptr()), TIM1_SR),
        (a(t.egr().as_ptr()), TIM1_EGR),
        (a(t.ccmr_output(0).as_ptr()), TIM1_CCMR1),
        (a(t.ccmr_output(1).as_ptr()), TIM1_CCMR2),
        (a(t.ccer().as_ptr()), TIM1_CCER),
        (a(t.cnt().as_ptr()), TIM1_CNT),
        (a(t.psc().as_ptr()), TIM1_PSC),
        (a(t.arr().as_ptr()), TIM1_ARR),
        (a(t.rcr().as_ptr()), TIM1_RCR),
        (a(t.ccr(0).as_ptr()), TIM1_CCR1),
        (a(t.ccr(1).as_ptr()), TIM1_CCR2),
        (a(t.ccr(2).as_ptr()), TIM1_CCR3),
        (a(t.ccr(3).as_ptr()), TIM1_CCR4),
        (a(t.bdtr().as_ptr()), TIM1_BDTR),
        (a(t.dcr().as_ptr()), TIM1_DCR),
        (a(t.dmar().as_ptr()), TIM1_DMAR),
    ];
    let t2 = pac::TIM2;
    let tim2 = [
        (a(t2.cr1().as_ptr()), TIM2_CR1),
        (a(t2.cr2().as_ptr()), TIM2_CR2),
        (a(t2.smcr().as_ptr()), TIM2_SMCR),
        (a(t2.dier().as_ptr()), TIM2_DIER),
        (a(t2.sr().as_ptr()), TIM2_SR),
        (a(t2.egr().as_ptr()), TIM2_EGR),
        (a(t2.cnt().as_ptr()), TIM2_CNT),
        (a(t2.psc().as_ptr()), TIM2_PSC),
        (a(t2.arr().as_ptr()), TIM2_ARR),
        (a(t2.or().as_ptr()), TIM2 + off::OR),
    ];
    let t11 = pac::TIM11;
    let tim11 = [
        (a(t11.cr1().as_ptr()), TIM11_CR1),
        (a(t11.dier().as_ptr()), TIM11_DIER),
        (a(t11.sr().as_ptr()), TIM11_SR),
        (a(t11.egr().as_ptr()), TIM11_EGR),
        (a(t11.cnt().as_ptr()), TIM11_CNT),
        (a(t11.psc().as_ptr()), TIM11_PSC),
        (a(t11.arr().as_ptr()), TIM11_ARR),
    ];
    for (pac_addr, ours) in tim1.into_iter().chain(tim2).chain(tim11) {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
}

/// A general-purpose timer's registers at `base` + `off`'s offsets (TIM3..5:
/// the edge times' TIM3 and TIM5, the cutter's count in TIM4).
macro_rules! gp_timer_pairs {
    ($t:expr, $base:expr) => {{
        let t = $t;
        [
            (a(t.cr1().as_ptr()), $base + off::CR1),
            (a(t.cr2().as_ptr()), $base + off::CR2),
            (a(t.smcr().as_ptr()), $base + off::SMCR),
            (a(t.dier().as_ptr()), $base + off::DIER),
            (a(t.sr().as_ptr()), $base + off::SR),
            (a(t.egr().as_ptr()), $base + off::EGR),
            (a(t.ccmr_input(0).as_ptr()), $base + off::CCMR1),
            (a(t.ccmr_input(1).as_ptr()), $base + off::CCMR2),
            (a(t.ccer().as_ptr()), $base + off::CCER),
            (a(t.cnt().as_ptr()), $base + off::CNT),
            (a(t.psc().as_ptr()), $base + off::PSC),
            (a(t.arr().as_ptr()), $base + off::ARR),
            (a(t.ccr(0).as_ptr()), $base + off::CCR1),
            (a(t.ccr(1).as_ptr()), $base + off::CCR2),
            (a(t.ccr(2).as_ptr()), $base + off::CCR3),
            (a(t.ccr(3).as_ptr()), $base + off::CCR4),
            (a(t.dcr().as_ptr()), $base + off::DCR),
            (a(t.dmar().as_ptr()), $base + off::DMAR),
        ]
    }};
}

#[test]
fn general_purpose_timer_offsets_match_metapac() {
    let pairs = gp_timer_pairs!(pac::TIM3, TIM3)
        .into_iter()
        .chain(gp_timer_pairs!(pac::TIM4, TIM4))
        .chain(gp_timer_pairs!(pac::TIM5, TIM5));
    for (pac_addr, ours) in pairs {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
    let t10 = pac::TIM10;
    let tim10 = [
        (a(t10.cr1().as_ptr()), TIM10 + off::CR1),
        (a(t10.dier().as_ptr()), TIM10 + off::DIER),
        (a(t10.sr().as_ptr()), TIM10 + off::SR),
        (a(t10.egr().as_ptr()), TIM10 + off::EGR),
        (a(t10.ccmr_output(0).as_ptr()), TIM10 + off::CCMR1),
        (a(t10.ccer().as_ptr()), TIM10 + off::CCER),
        (a(t10.cnt().as_ptr()), TIM10 + off::CNT),
        (a(t10.psc().as_ptr()), TIM10 + off::PSC),
        (a(t10.arr().as_ptr()), TIM10 + off::ARR),
        (a(t10.ccr(0).as_ptr()), TIM10 + off::CCR1),
    ];
    for (pac_addr, ours) in tim10 {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
}

#[test]
fn tim9_addresses_match_metapac() {
    let t = pac::TIM9;
    let pairs = [
        (a(t.cr1().as_ptr()), TIM9_CR1),
        (a(t.smcr().as_ptr()), TIM9_SMCR),
        (a(t.dier().as_ptr()), TIM9_DIER),
        (a(t.sr().as_ptr()), TIM9_SR),
        (a(t.egr().as_ptr()), TIM9_EGR),
        (a(t.ccmr_output(0).as_ptr()), TIM9_CCMR1),
        (a(t.ccer().as_ptr()), TIM9_CCER),
        (a(t.cnt().as_ptr()), TIM9_CNT),
        (a(t.psc().as_ptr()), TIM9_PSC),
        (a(t.arr().as_ptr()), TIM9_ARR),
        (a(t.ccr(0).as_ptr()), TIM9_CCR1),
        (a(t.ccr(1).as_ptr()), TIM9_CCR2),
    ];
    for (pac_addr, ours) in pairs {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
}

#[test]
fn dma_register_addresses_match_metapac() {
    let d = pac::DMA2;
    let s = d.st(5);
    let pairs = [
        (a(d.isr(0).as_ptr()), DMA2_LISR),
        (a(d.isr(1).as_ptr()), DMA2_HISR),
        (a(d.ifcr(0).as_ptr()), DMA2_LIFCR),
        (a(d.ifcr(1).as_ptr()), DMA2_HIFCR),
        (a(s.cr().as_ptr()), DMA2_S5CR),
        (a(s.ndtr().as_ptr()), DMA2_S5NDTR),
        (a(s.par().as_ptr()), DMA2_S5PAR),
        (a(s.m0ar().as_ptr()), DMA2_S5M0AR),
        (a(s.m1ar().as_ptr()), DMA2_S5M1AR),
        (a(s.fcr().as_ptr()), DMA2_S5FCR),
    ];
    for (pac_addr, ours) in pairs {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
}

#[test]
fn gpio_crc_and_rcc_register_addresses_match_metapac() {
    let g = pac::GPIOA;
    let pairs = [
        (a(g.moder().as_ptr()), GPIOA + gpio_off::MODER),
        (a(g.otyper().as_ptr()), GPIOA + gpio_off::OTYPER),
        (a(g.ospeedr().as_ptr()), GPIOA + gpio_off::OSPEEDR),
        (a(g.pupdr().as_ptr()), GPIOA + gpio_off::PUPDR),
        (a(g.idr().as_ptr()), GPIOA + gpio_off::IDR),
        (a(g.odr().as_ptr()), GPIOA + gpio_off::ODR),
        (a(g.bsrr().as_ptr()), GPIOA + gpio_off::BSRR),
        (a(g.lckr().as_ptr()), GPIOA + gpio_off::LCKR),
        (a(g.afr(0).as_ptr()), GPIOA + gpio_off::AFRL),
        (a(g.afr(1).as_ptr()), GPIOA + gpio_off::AFRH),
        (a(pac::GPIOC.bsrr().as_ptr()), GPIOC + gpio_off::BSRR),
        (a(pac::CRC.dr().as_ptr()), CRC_DR),
        (a(pac::CRC.idr().as_ptr()), CRC + crc_off::IDR),
        (a(pac::CRC.cr().as_ptr()), CRC_CR),
        (a(pac::RCC.ahb1enr().as_ptr()), RCC_AHB1ENR),
    ];
    for (pac_addr, ours) in pairs {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
}

#[test]
fn gpio_and_flash_register_addresses_match_metapac() {
    let pairs = [
        (a(pac::GPIOA.idr().as_ptr()), GPIOA_IDR),
        (a(pac::GPIOA.bsrr().as_ptr()), GPIOA_BSRR),
        (a(pac::GPIOB.idr().as_ptr()), GPIOB_IDR),
        (a(pac::FLASH.keyr().as_ptr()), FLASH_KEYR),
        (a(pac::FLASH.sr().as_ptr()), FLASH_SR),
        (a(pac::FLASH.cr().as_ptr()), FLASH_CR),
    ];
    for (pac_addr, ours) in pairs {
        assert_eq!(pac_addr, ours, "{ours:#010x}");
    }
}

// RM0383 §9.3.3/§9.3.4 DMA2 request mapping: stream 5, channel 6 = TIM1_UP.
#[test]
fn tim1_up_is_dma2_stream_5_channel_6_in_metapac() {
    let tim1 = pac::metadata::METADATA.peripherals.iter().find(|p| p.name == "TIM1").unwrap();
    let up: Vec<_> = tim1.dma_channels.iter().filter(|c| c.signal == "UP").collect();
    assert_eq!(up.len(), 1);
    assert_eq!((up[0].channel, up[0].request), (Some("DMA2_CH5"), Some(6)));
}

// The pins and the vector the quadrature generator relies on: PA2 = TIM9_CH1 and
// PA3 = TIM9_CH2 on AF3, TIM9's update on the TIM1_BRK_TIM9 vector (position 24).
#[test]
fn tim9_pins_and_interrupt_match_metapac() {
    let p = pac::metadata::METADATA.peripherals.iter().find(|p| p.name == "TIM9").unwrap();
    let pin = |name: &str| p.pins.iter().find(|x| x.pin == name).map(|x| (x.signal, x.af));
    assert_eq!(pin("PA2"), Some(("CH1", Some(3))));
    assert_eq!(pin("PA3"), Some(("CH2", Some(3))));
    let up = p.interrupts.iter().find(|i| i.signal == "UP").unwrap();
    assert_eq!(up.interrupt, "TIM1_BRK_TIM9");
    assert_eq!(pac::Interrupt::TIM1_BRK_TIM9 as u16, 24);
}
