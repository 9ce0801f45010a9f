//! DMA bit fields, built with `stm32-metapac`'s setters (ST's SVD data as curated by
//! the embassy project) and compared with `bits`.
use polyturn_regs::bits::*;
use stm32_metapac::dma::regs as dregs;
use stm32_metapac::dma::vals as dvals;

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
    assert_eq!(bits!(Cr, |r| r.set_pl(dvals::Pl::VERY_HIGH)), dma_cr::PL.val(dma_cr::PL_VERY_HIGH));
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

#[test]
fn stream_5s_flag_clears_match_metapac() {
    use dregs::Ixr;
    // HIFCR: metapac's index 1 is stream 5, the second stream of the register
    assert_eq!(bits!(Ixr, |r| r.set_feif(1, true)), hifcr::CFEIF5.mask());
    let four = bits!(Ixr, |r| {
        r.set_dmeif(1, true);
        r.set_teif(1, true);
        r.set_htif(1, true);
        r.set_tcif(1, true);
    });
    assert_eq!(four, hifcr::CDMEIF5_TO_CTCIF5.mask(), "stream 5's DME, TE, HT and TC flags");
}
