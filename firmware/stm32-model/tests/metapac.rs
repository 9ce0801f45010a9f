//! Every address and bit position the model decodes, checked against `stm32-metapac`
//! (ST's SVD data as curated by the embassy project), so that none of them rests on a
//! hand reading of the manual alone.
use polyturn_stm32_model::addr::*;
use polyturn_stm32_model::bits::*;
use stm32_metapac as pac;
use stm32_metapac::dma::regs as dregs;
use stm32_metapac::dma::vals as dvals;

fn a<T>(p: *mut T) -> u32 {
    p as usize as u32
}

#[test]
fn base_addresses_and_sram_match_metapac() {
    assert_eq!(a(pac::TIM1.as_ptr()), TIM1);
    assert_eq!(a(pac::TIM2.as_ptr()), TIM2);
    assert_eq!(a(pac::TIM11.as_ptr()), TIM11);
    assert_eq!(a(pac::DMA2.as_ptr()), DMA2);
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

#[macro_use]
mod build_bits;

#[test]
fn dma_bit_fields_match_metapac() {
    use dregs::{Cr, Fcr, Ixr, Ndtr};
    assert_eq!(bits!(Cr, |r| r.set_en(true)), dma_cr::EN.mask());
    assert_eq!(bits!(Cr, |r| r.set_dmeie(true)), dma_cr::DMEIE.mask());
    assert_eq!(bits!(Cr, |r| r.set_teie(true)), dma_cr::TEIE.mask());
    assert_eq!(bits!(Cr, |r| r.set_htie(true)), dma_cr::HTIE.mask());
    assert_eq!(bits!(Cr, |r| r.set_tcie(true)), dma_cr::TCIE.mask());
    assert_eq!(bits!(Cr, |r| r.set_pfctrl(dvals::Pfctrl::PERIPHERAL)), dma_cr::PFCTRL.mask());
    assert_eq!(bits!(Cr, |r| r.set_dir(dvals::Dir::MEMORY_TO_PERIPHERAL)), dma_cr::DIR.val(dma_cr::DIR_M2P));
    assert_eq!(bits!(Cr, |r| r.set_dir(dvals::Dir::from_bits(3))), dma_cr::DIR.mask());
    assert_eq!(bits!(Cr, |r| r.set_circ(true)), dma_cr::CIRC.mask());
    assert_eq!(bits!(Cr, |r| r.set_pinc(true)), dma_cr::PINC.mask());
    assert_eq!(bits!(Cr, |r| r.set_minc(true)), dma_cr::MINC.mask());
    assert_eq!(bits!(Cr, |r| r.set_psize(dvals::Size::BITS16)), dma_cr::PSIZE.val(dma_cr::SIZE_HALF));
    assert_eq!(bits!(Cr, |r| r.set_psize(dvals::Size::BITS32)), dma_cr::PSIZE.val(dma_cr::SIZE_WORD));
    assert_eq!(bits!(Cr, |r| r.set_psize(dvals::Size::from_bits(3))), dma_cr::PSIZE.mask());
    assert_eq!(bits!(Cr, |r| r.set_msize(dvals::Size::from_bits(3))), dma_cr::MSIZE.mask());
    assert_eq!(bits!(Cr, |r| r.set_pincos(dvals::Pincos::FIXED4)), dma_cr::PINCOS.mask());
    assert_eq!(bits!(Cr, |r| r.set_pl(dvals::Pl::VERY_HIGH)), dma_cr::PL.mask());
    assert_eq!(bits!(Cr, |r| r.set_dbm(true)), dma_cr::DBM.mask());
    assert_eq!(bits!(Cr, |r| r.set_ct(dvals::Ct::MEMORY1)), dma_cr::CT.mask());
    assert_eq!(bits!(Cr, |r| r.set_pburst(dvals::Burst::INCR16)), dma_cr::PBURST.mask());
    assert_eq!(bits!(Cr, |r| r.set_mburst(dvals::Burst::INCR16)), dma_cr::MBURST.mask());
    assert_eq!(bits!(Cr, |r| r.set_chsel(7)), dma_cr::CHSEL.mask());
    assert_eq!(bits!(Cr, |r| r.set_chsel(6)), dma_cr::CHSEL.val(6));

    assert_eq!(bits!(Fcr, |r| r.set_fth(dvals::Fth::FULL)), dma_fcr::FTH.mask());
    assert_eq!(bits!(Fcr, |r| r.set_dmdis(dvals::Dmdis::DISABLED)), dma_fcr::DMDIS.mask());
    assert_eq!(bits!(Fcr, |r| r.set_fs(dvals::Fs::from_bits(7))), dma_fcr::FS.mask());
    assert_eq!(bits!(Fcr, |r| r.set_feie(true)), dma_fcr::FEIE.mask());
    assert_eq!(bits!(Ndtr, |r| r.set_ndt(0xFFFF)), dma_fcr::NDT.mask());

    // HISR/HIFCR: metapac's index n is the stream within the register (stream 4 + n).
    for s in 4..8u32 {
        let n = (s - 4) as usize;
        assert_eq!(bits!(Ixr, |r| r.set_feif(n, true)), dma_isr::feif(s).mask());
        assert_eq!(bits!(Ixr, |r| r.set_dmeif(n, true)), dma_isr::dmeif(s).mask());
        assert_eq!(bits!(Ixr, |r| r.set_teif(n, true)), dma_isr::teif(s).mask());
        assert_eq!(bits!(Ixr, |r| r.set_htif(n, true)), dma_isr::htif(s).mask());
        assert_eq!(bits!(Ixr, |r| r.set_tcif(n, true)), dma_isr::tcif(s).mask());
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
