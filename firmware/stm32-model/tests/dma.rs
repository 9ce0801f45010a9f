//! DMA2 stream 5 serving TIM1_UP, and TIM1's DMA burst: one test per manual statement.
mod common;
use common::*;

const BUF: u32 = SRAM_BASE + 0x100;

/// A four-transfer burst from ARR ([100, 2, 30, 40] to ARR, RCR, CCR1,
/// CCR2), its first request raised by UG.
fn burst_from_arr_started() -> Mcu {
    let mut m = mcu();
    sram_u16(&mut m, BUF, &[100, 2, 30, 40]);
    dma5(&mut m, TIM1_DMAR, BUF, 4, dma_cr::SIZE_HALF, false);
    m.write(TIM1_DCR, dcr::DBA.val(off::ARR / 4) | dcr::DBL.val(3));
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    m
}

fn stream_en(m: &mut Mcu) -> bool {
    dma_cr::EN.on(m.read(DMA2_S5CR))
}

// §12.4.6 UG "Reinitialize the counter and generates an update of the registers ... the
// prescaler counter is cleared too"; §12.3.3 UG reloads REP_CNT; §12.4.1 URS = 0: UG
// raises the update DMA request (UDE). Brief (e).
#[test]
fn ug_reinitialises_cnt_transfers_preloads_reloads_rep_and_requests_dma() {
    let mut m = mcu();
    sram_u16(&mut m, BUF, &[777]);
    dma5(&mut m, TIM1_CCR2, BUF, 1, dma_cr::SIZE_HALF, false);
    m.write(TIM1_ARR, 100);
    start_tim1(&mut m, cr1::ARPE.mask());
    m.run_until(50);
    m.write(TIM1_ARR, 20);
    m.write(TIM1_PSC, 1);
    m.write(TIM1_RCR, 1);
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    assert_eq!(m.read(TIM1_CNT), 0);
    assert!(uif1(&mut m));
    m.write(TIM1_SR, 0);
    m.run_until(55);
    assert_eq!(m.read(TIM1_CCR2), 0, "DMA latency 6 not elapsed");
    m.run_until(56);
    assert_eq!(m.read(TIM1_CCR2), 777);
    m.run_until(90);
    assert_eq!(m.read(TIM1_CNT), 20, "PSC 1 active since the UG: one count per 2 cycles");
    m.run_until(92);
    assert_eq!(m.read(TIM1_CNT), 0, "ARR 20 active since the UG");
    assert!(!uif1(&mut m), "REP_CNT reloaded with 1: this overflow is not an update");
    m.run_until(134);
    assert!(uif1(&mut m));
}

// §12.4.1 URS = 1: "Only counter overflow/underflow generates an update interrupt or DMA
// request"; UDIS = 1: no update event at all.
#[test]
fn ug_raises_no_dma_request_with_urs_or_udis() {
    for cr1_bits in [cr1::URS.mask(), cr1::UDIS.mask()] {
        let mut m = mcu();
        sram_u16(&mut m, BUF, &[777]);
        dma5(&mut m, TIM1_CCR2, BUF, 1, dma_cr::SIZE_HALF, false);
        m.write(TIM1_CR1, cr1_bits);
        m.write(TIM1_DIER, dier::UDE.mask());
        m.write(TIM1_EGR, egr::UG.mask());
        m.run_until(100);
        assert_eq!(m.read(TIM1_CCR2), 0);
        assert_eq!(m.read(DMA2_S5NDTR), 1);
    }
}

// §12.4.20 DMAR: an access reaches "(TIMx_CR1 address) + (DBA + DMA index) x 4 ... DMA
// index ... ranges from 0 to DBL"; §12.4.19 DBL = 3 means 4 transfers. Brief (f):
// DBA = 11 (ARR), DBL = 3 → ARR, RCR, CCR1, CCR2, one transfer per latency.
#[test]
fn dma_burst_from_arr_writes_arr_rcr_ccr1_ccr2_in_order() {
    let mut m = burst_from_arr_started();
    let regs = [TIM1_ARR, TIM1_RCR, TIM1_CCR1, TIM1_CCR2];
    let mut seen = Vec::new();
    for cycle in 1..=24 {
        m.run_until(cycle);
        seen.push(regs.map(|r| m.read(r)));
    }
    assert_eq!(seen[4], [0, 0, 0, 0]);
    assert_eq!(seen[5], [100, 0, 0, 0]);
    assert_eq!(seen[11], [100, 2, 0, 0]);
    assert_eq!(seen[17], [100, 2, 30, 0]);
    assert_eq!(seen[23], [100, 2, 30, 40]);
    assert_eq!(m.read(DMA2_S5NDTR), 0);
    assert!(!stream_en(&mut m), "normal mode: EN cleared at NDTR = 0 (§9.5.5)");
    assert_eq!(m.dma_requests_lost(), 0);
}

// §9.5.5 PSIZE = word: 32-bit items, memory pointer advancing by 4 (§9.3.7).
#[test]
fn word_sized_burst_reads_consecutive_words() {
    let mut m = Mcu::new(Params { dma_latency_cycles: 3, ..Params::default() });
    for (i, v) in [9u32, 7].iter().enumerate() {
        m.write(BUF + 4 * i as u32, *v);
    }
    dma5(&mut m, TIM1_DMAR, BUF, 2, dma_cr::SIZE_WORD, false);
    m.write(TIM1_DCR, dcr::DBA.val(off::CCR1 / 4) | dcr::DBL.val(1));
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    m.run_until(3);
    assert_eq!((m.read(TIM1_CCR1), m.read(TIM1_CCR2)), (9, 0));
    m.run_until(6);
    assert_eq!((m.read(TIM1_CCR1), m.read(TIM1_CCR2)), (9, 7));
}

// §9.3.8 "Circular mode": "the number of data items to be transferred is automatically
// reloaded with the initial value ... and the DMA requests continue to be served";
// §9.4 half-transfer and transfer-complete flags, cleared through HIFCR (§9.5.4).
#[test]
fn circular_mode_wraps_the_pointer_and_reloads_ndtr() {
    let mut m = mcu();
    sram_u16(&mut m, BUF, &[11, 22]);
    dma5(&mut m, TIM1_CCR2, BUF, 2, dma_cr::SIZE_HALF, true);
    m.write(TIM1_ARR, 9);
    m.write(TIM1_DIER, dier::UDE.mask());
    start_tim1(&mut m, 0); // overflows at cycles 11, 21, 31, 41
    let (ht, tc) = (dma_isr::htif(5).mask(), dma_isr::tcif(5).mask());
    let mut got = Vec::new();
    for k in 0..4 {
        m.run_until(17 + 10 * k);
        got.push((m.read(TIM1_CCR2), m.read(DMA2_S5NDTR), m.read(DMA2_HISR) & (ht | tc)));
        m.write(DMA2_HIFCR, ht | tc);
    }
    assert_eq!(got, [(11, 1, ht), (22, 2, tc), (11, 1, ht), (22, 2, tc)]);
    assert!(stream_en(&mut m));
    assert_eq!(m.read(DMA2_HISR), 0);
}

// §9.5.6 NDTR: "If the value of this register is zero ... (normal mode) ... reloaded
// automatically with the previously programmed value ... when the stream is enabled again."
#[test]
fn ndtr_is_reloaded_when_the_stream_is_enabled_again() {
    let mut m = mcu();
    dma5(&mut m, TIM1_CCR2, BUF, 1, dma_cr::SIZE_HALF, false);
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    m.run_until(10);
    assert_eq!(m.read(DMA2_S5NDTR), 0);
    m.write(DMA2_HIFCR, dma_isr::tcif(5).mask() | dma_isr::htif(5).mask());
    let cr = m.read(DMA2_S5CR);
    m.write(DMA2_S5CR, cr | dma_cr::EN.mask());
    assert_eq!(m.read(DMA2_S5NDTR), 1);
}

// §9.5.5-§9.5.8: CR, NDTR, PAR and M0AR "can be written only when the stream is disabled".
#[test]
fn configuration_registers_ignore_writes_while_enabled() {
    let mut m = mcu();
    dma5(&mut m, TIM1_CCR2, BUF, 3, dma_cr::SIZE_HALF, false);
    let cr = m.read(DMA2_S5CR);
    m.write(DMA2_S5NDTR, 9);
    m.write(DMA2_S5PAR, TIM1_CCR1);
    m.write(DMA2_S5M0AR, BUF + 8);
    m.write(DMA2_S5CR, cr | dma_cr::CIRC.mask());
    assert_eq!(m.read(DMA2_S5NDTR), 3);
    assert_eq!(m.read(DMA2_S5PAR), TIM1_CCR2);
    assert_eq!(m.read(DMA2_S5M0AR), BUF);
    assert_eq!(m.read(DMA2_S5CR), cr);
}

// §9.5.5 MSIZE: "In direct mode, MSIZE is forced by hardware to the same value as PSIZE
// as soon as bit EN = '1'".
#[test]
fn direct_mode_forces_msize_to_psize_on_enable() {
    let mut m = mcu();
    m.write(DMA2_S5PAR, TIM1_CCR1);
    m.write(DMA2_S5NDTR, 1);
    let cr = dma_cr::CHSEL.val(6) | dma_cr::DIR.val(1) | dma_cr::PSIZE.val(1) | dma_cr::MSIZE.val(2);
    m.write(DMA2_S5CR, cr | dma_cr::EN.mask());
    assert_eq!(dma_cr::MSIZE.get(m.read(DMA2_S5CR)), 1);
}

// §9.3.14 "DMA transfer suspension": after EN is cleared "the stream may take time to be
// disabled (ongoing transfer is completed first). The transfer complete interrupt flag
// (TCIF ...) is set"; NDTR keeps the remaining count.
#[test]
fn clearing_en_stops_the_stream_after_the_transfer_in_flight() {
    let mut m = burst_from_arr_started();
    m.run_until(2);
    let cr = m.read(DMA2_S5CR);
    m.write(DMA2_S5CR, cr & !dma_cr::EN.mask());
    assert!(stream_en(&mut m), "EN reads 1 until the transfer in flight completes");
    m.run_until(6);
    assert!(!stream_en(&mut m));
    assert!(dma_isr::tcif(5).on(m.read(DMA2_HISR)));
    assert_eq!(m.read(DMA2_S5NDTR), 3);
    m.run_until(40);
    assert_eq!((m.read(TIM1_ARR), m.read(TIM1_RCR)), (100, 0), "rest of the burst lost");
}

// §9.3.2: the peripheral keeps its request until the DMA acknowledges it, so an update
// while the previous request (here a 4-transfer burst, 24 cycles) is pending merges with
// it. The model counts such merges in `dma_requests_lost`.
#[test]
fn an_update_while_the_previous_request_is_pending_is_merged_and_counted() {
    let mut m = mcu();
    sram_u16(&mut m, BUF, &[9, 0, 5, 5]); // ARR, RCR, CCR1, CCR2
    dma5(&mut m, TIM1_DMAR, BUF, 4, dma_cr::SIZE_HALF, true);
    m.write(TIM1_DCR, dcr::DBA.val(off::ARR / 4) | dcr::DBL.val(3));
    m.write(TIM1_ARR, 9);
    m.write(TIM1_DIER, dier::UDE.mask());
    start_tim1(&mut m, 0); // updates at 11, 21, 31: the burst from 11 ends at 35
    m.run_until(34);
    assert_eq!(m.dma_requests_lost(), 2);
}

// Brief: requests while EN = 0 are lost (the stream only serves requests while enabled).
#[test]
fn update_requests_while_the_stream_is_disabled_are_lost() {
    let mut m = mcu();
    sram_u16(&mut m, BUF, &[5]);
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    assert_eq!(m.dma_requests_lost(), 1);
    dma5(&mut m, TIM1_CCR2, BUF, 1, dma_cr::SIZE_HALF, false);
    m.run_until(50);
    assert_eq!(m.read(TIM1_CCR2), 0);
}

// §9.3.12 direct mode: "the DMA preloads only one data from the memory to the internal
// FIFO to ensure an immediate data transfer as soon as a DMA request is triggered". The
// item is read from RAM when the stream is enabled and after each transfer, so a later
// write to that word does not reach the peripheral (firmware that writes a burst's first
// word after enabling the stream sends the word that was there before).
#[test]
fn direct_mode_reads_the_next_item_before_its_request() {
    let mut m = mcu();
    sram_u16(&mut m, BUF, &[111, 222]);
    dma5(&mut m, TIM1_CCR2, BUF, 2, dma_cr::SIZE_HALF, false);
    // overwritten after the enable: the stream already holds 111
    sram_u16(&mut m, BUF, &[999, 222]);
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    m.run_until(20);
    assert_eq!(m.read(TIM1_CCR2), 111, "the item read at enable");
    // the second item was read right after the first transfer
    sram_u16(&mut m, BUF, &[0, 888]);
    m.write(TIM1_EGR, egr::UG.mask());
    m.run_until(40);
    assert_eq!(m.read(TIM1_CCR2), 222, "the item read after the previous transfer");
}

// The second reading of NDTR (Params::ndtr = AtPreload): it counts the word direct mode
// preloads at enable and after each transfer (§9.2 "preloads only one data", §9.3.12), so
// it reads one less than the transfers done would leave, and in circular mode the count
// that reaches 0 at the last item's preload reads the programmed length (§9.3.8 reload).
// On the manual's reading (AfterTransfer) it counts transfers only (§9.3.2).
#[test]
fn ndtr_counts_the_preloaded_word_only_on_the_preload_reading() {
    let run = |ndtr| {
        let mut m = Mcu::new(Params { ndtr, ..Params::default() });
        sram_u16(&mut m, BUF, &[11, 22, 33]);
        dma5(&mut m, TIM1_CCR2, BUF, 3, dma_cr::SIZE_HALF, true);
        let mut seen = vec![m.read(DMA2_S5NDTR)];
        m.write(TIM1_ARR, 9);
        m.write(TIM1_DIER, dier::UDE.mask());
        start_tim1(&mut m, 0); // overflows at cycles 11, 21, 31, 41
        for k in 0..4 {
            m.run_until(17 + 10 * k);
            seen.push(m.read(DMA2_S5NDTR));
        }
        seen
    };
    assert_eq!(run(NdtrReading::AfterTransfer), [3, 2, 1, 3, 2]);
    assert_eq!(run(NdtrReading::AtPreload), [2, 1, 3, 2, 1]);
}
