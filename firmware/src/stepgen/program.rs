//! The register writes the MCU performs on the step output, as data: the
//! MCU applies these lists verbatim (`apply`, through a five-line `Bus` over
//! volatile pointers) and the host runs the same lists through a model of
//! the peripherals written from RM0383 (`polyturn-stm32-model`).
//!
//! Addresses: RM0383 §2.3 (memory map), §12.4.21 (TIM1 register map),
//! §13.4.21 (TIM2), §14.5.12 (TIM11), §9.5.11 (DMA). Bit positions: the
//! register descriptions of the same chapters. Both are `polyturn_regs`',
//! checked there against ST's SVD (stm32-metapac).

pub use crate::regs::{apply, Bus, Op};
use polyturn_regs::bits::{bdtr, ccer, ccmr, cr1, cr2, dcr, dier, dma_cr, egr, hifcr, ocm, smcr, sr};

pub use polyturn_regs::addr::{DMA2, TIM1, TIM11, TIM2};

// timer register offsets (§12.4.21)
pub use polyturn_regs::addr::off::{
    ARR, BDTR, CCER, CCMR1, CCR1, CCR2, CNT, CR1, CR2, DCR, DIER, DMAR, EGR, PSC, RCR, SMCR, SR,
};

// DMA2 stream 5 (§9.5.11: SxCR at 0x10 + 0x18 × x)
pub use polyturn_regs::addr::{
    DMA2_HIFCR as HIFCR, DMA2_S5CR as S5CR, DMA2_S5FCR as S5FCR, DMA2_S5M0AR as S5M0AR, DMA2_S5NDTR as S5NDTR,
    DMA2_S5PAR as S5PAR,
};

// TIMx_CR1 (§12.4.1). URS: only an overflow sets UIF and requests DMA, so
// a UG never starts a burst (UIF set by a UG could otherwise request one
// the moment UDE is set)
const CEN: u32 = cr1::CEN.mask();
/// TIMx_SR.UIF (§12.4.5): set by every update event the counter makes
pub const UIF: u32 = sr::UIF.mask();
const URS: u32 = cr1::URS.mask();
const ARPE: u32 = cr1::ARPE.mask();
const CR1_STOPPED: u32 = ARPE | URS;
// TIMx_CR2.MMS = 100: OC1REF is TRGO (§12.4.2), TIM2 counts it
const MMS_OC1REF: u32 = cr2::MMS.val(cr2::MMS_OC1REF);
// TIMx_SMCR (§13.4.3): SMS = 111 external clock mode 1, TS = 000 ITR0 (TIM1)
const SMS_ECM1: u32 = smcr::SMS.val(smcr::SMS_EXT_CLOCK_1) | smcr::TS.val(0);
// TIMx_DIER.UDE (§12.4.4)
const UDE: u32 = dier::UDE.mask();
// TIMx_EGR.UG (§12.4.6)
const UG: u32 = egr::UG.mask();
// TIMx_CCMR1 output (§12.4.7): OC1M bits 6:4, OC1PE bit 3, OC2M 14:12, OC2PE 11
const OC1_PWM2: u32 = ccmr::OC1M.val(ocm::PWM2);
const OC1_FORCE_LOW: u32 = ccmr::OC1M.val(ocm::FORCE_INACTIVE);
const OC2_PWM1: u32 = ccmr::OC2M.val(ocm::PWM1);
const PRELOADS: u32 = ccmr::OC1PE.mask() | ccmr::OC2PE.mask();
/// STEP in PWM mode 2 (low until CCR1, then high to the end of the
/// segment); DIR in PWM mode 1 (high while CNT < CCR2)
pub const CCMR1_RUN: u32 = OC1_PWM2 | OC2_PWM1 | PRELOADS;
/// STEP forced low at once; DIR unchanged
pub const CCMR1_HALT: u32 = OC1_FORCE_LOW | OC2_PWM1 | PRELOADS;
// TIMx_CCER (§12.4.9): CC1E bit 0, CC2E bit 4, active high
const CC1E_CC2E: u32 = ccer::CC1E.mask() | ccer::CC2E.mask();
// TIMx_BDTR.MOE (§12.4.18): an advanced timer's outputs need it
const MOE: u32 = bdtr::MOE.mask();
/// TIMx_DCR (§12.4.19): DMA bursts start at PSC (offset 0x28 / 4 = 10) and
/// write 5 registers: PSC, ARR, RCR, CCR1, CCR2 (`entries::Entry::words`)
pub const DCR_BURST: u32 = dcr::DBL.val(BURST_WORDS - 1) | dcr::DBA.val(PSC / 4);
pub const BURST_WORDS: u32 = 5;

/// DMA2_S5CR (§9.5.5): channel 6 (TIM1_UP on stream 5, table 28), very
/// high priority, words from memory (incremented) to the peripheral,
/// circular.
pub const S5CR_RUN: u32 = dma_cr::CHSEL.val(6)
    | dma_cr::PL.val(dma_cr::PL_VERY_HIGH)
    | dma_cr::MSIZE.val(dma_cr::SIZE_WORD)
    | dma_cr::PSIZE.val(dma_cr::SIZE_WORD)
    | dma_cr::MINC.mask()
    | dma_cr::CIRC.mask()
    | dma_cr::DIR.val(dma_cr::DIR_M2P);
pub const DMA_EN: u32 = dma_cr::EN.mask();
/// HIFCR: clear every flag of stream 5 (bits 6, 8–11)
const STREAM5_FLAGS: u32 = hifcr::CDMEIF5_TO_CTCIF5.mask() | hifcr::CFEIF5.mask();

/// TIM2 counts TIM1's OC1REF rising edges: every STEP pulse.
pub const COUNTER_INIT: [Op; 3] =
    [Op::Write(TIM2 + SMCR, SMS_ECM1), Op::Write(TIM2 + ARR, u32::MAX), Op::Write(TIM2 + CR1, CEN)];

/// `halt`'s first write, alone: the counter stops, so no STEP pulse rises
/// after it. The E-stop interrupt writes it before anything else.
pub const STOP: Op = Op::Write(TIM1 + CR1, CR1_STOPPED);

/// Stops the output at once without a runt: the counter stops first, so no
/// pulse rises after it (§12.3.2: the counter counts only while CEN = 1,
/// and OC1REF follows CNT against CCR1); DMA requests end and the stream
/// stops. A pulse that was high stays high, the counter frozen under it:
/// `RELEASE` forces STEP low once it has been high for its whole width
/// (`release_ticks` later, or `halt_and_wait`), so the driver sees every
/// pulse TIM2 counted and no handler waits for it.
pub const HALT: [Op; 3] = [STOP, Op::Write(TIM1 + DIER, 0), Op::Write(S5CR, S5CR_RUN)];

/// STEP forced low (§12.4.7, OC1M = 100), DIR kept: after `HALT`, once a
/// pulse that was high has had its width.
pub const RELEASE: Op = Op::Write(TIM1 + CCMR1, CCMR1_HALT);

/// `HALT` and `RELEASE` as the handlers apply them: in RAM on the MCU. A
/// constant in flash would be read through the ART accelerator's data
/// cache (RM0383 §3.4), a wait the emulator's clock does not charge for a
/// load by address; `.ci/callgraph` checks the handlers make none.
#[cfg_attr(target_os = "none", link_section = ".data.stepgen_halt")]
pub static HALT_IN_RAM: [Op; 3] = HALT;
#[cfg_attr(target_os = "none", link_section = ".data.stepgen_release")]
pub static RELEASE_IN_RAM: [Op; 1] = [RELEASE];

/// Whole ticks after a `HALT` made at any point of a tick of `tick_len`
/// cycles at whose start `RELEASE` may come: a pulse that rose just before
/// the halt has had `pulse` cycles by then (at least `ticks - 1` whole
/// ticks pass).
pub const fn release_ticks(pulse: u32, tick_len: u32) -> u32 {
    // (max(1): no division-by-zero panic path in the handlers)
    pulse.div_ceil(if tick_len == 0 { 1 } else { tick_len }) + 1
}

/// `HALT`, the wait for a high pulse's width, and `RELEASE`, all at once:
/// where nothing comes later to release it (the panic and fault handlers).
pub const fn halt_and_wait(pulse: u32) -> [Op; 5] {
    [HALT[0], HALT[1], HALT[2], Op::Delay(pulse), RELEASE]
}

/// Cycles from reading TIM11's counter to the write of TIM1's landing, in
/// `Sync`: a load, an add and a store on the APB2 bus. Any error is a
/// fixed offset of every step (a few ns), measured on the bench.
pub const SYNC_CYCLES: u32 = 8;

/// Words in the DMA ring (entries × 5 registers).
pub const RING_WORDS: u32 = super::RING_ENTRIES as u32 * BURST_WORDS;

/// Stops everything and drives the outputs quietly: STEP low (forced),
/// DIR at `dir_level`, loaded by UG with DMA requests off. At boot, so the
/// pins are driven from then on (AF1 with the timer's outputs off would
/// leave them floating, §12.4.9), and a tick before each `arm` after a halt.
pub const fn quiet(tick_len: u32, dir_level: u32) -> [Op; 16] {
    [
        // stop: no requests, stream off and drained, counter stopped, STEP low
        Op::Write(TIM1 + DIER, 0),
        Op::Write(S5CR, S5CR_RUN),
        Op::WaitClear { addr: S5CR, mask: DMA_EN, polls: 64 },
        Op::Write(HIFCR, STREAM5_FLAGS),
        Op::Write(TIM1 + CR1, CR1_STOPPED),
        Op::Write(TIM1 + CCMR1, CCMR1_HALT),
        // TRGO = OC1REF (held low) before the UG: with MMS at its reset
        // value the UG itself is TRGO (§12.4.2), and TIM2 would count it
        Op::Write(TIM1 + CR2, MMS_OC1REF),
        // a silent segment of a tick, loaded at once by UG
        Op::Write(TIM1 + PSC, 0),
        Op::Write(TIM1 + ARR, tick_len - 1),
        Op::Write(TIM1 + RCR, 0),
        Op::Write(TIM1 + CCR1, super::entries::SILENT),
        Op::Write(TIM1 + CCR2, dir_level),
        Op::Write(TIM1 + EGR, UG),
        Op::Write(TIM1 + CCER, CC1E_CC2E),
        Op::Write(TIM1 + BDTR, MOE),
        Op::Write(TIM1 + SR, 0),
    ]
}

/// The stream on over the ring as `arm` sets it, TIM1 left stopped with no
/// DMA request enabled: at boot, after `quiet`, to see whether NDTR counts
/// the word direct mode preloads (`Generator::prepare`).
pub const fn probe(ring: u32) -> [Op; 5] {
    [
        Op::Write(S5PAR, TIM1 + DMAR),
        Op::Write(S5M0AR, ring),
        Op::Write(S5NDTR, RING_WORDS),
        Op::Write(S5FCR, 0),
        Op::Write(S5CR, S5CR_RUN | DMA_EN),
    ]
}

/// The probe's stream off again, its flags cleared (§9.3.17: a stream is
/// enabled only with them clear).
pub const PROBE_END: [Op; 3] =
    [Op::Write(S5CR, S5CR_RUN), Op::WaitClear { addr: S5CR, mask: DMA_EN, polls: 64 }, Op::Write(HIFCR, STREAM5_FLAGS)];

/// (Re-)arms the output once `quiet` has run, nothing since undoing it (a
/// tick before, or at boot: `Generator::begin`). The DMA ring at
/// `ring` must be silent. The counter runs one segment to the end of the
/// current tick (its count set from TIM11's, `Sync`), then a silent tick,
/// then the ring's first entry: the plan made in this tick, as
/// `steps::pipe` expects.
pub const fn arm(ring: u32, tick_len: u32) -> [Op; 10] {
    [
        // PWM mode only now: CNT = 0 < CCR1, so STEP stays low (no runt)
        Op::Write(TIM1 + CCMR1, CCMR1_RUN),
        Op::Write(TIM1 + DCR, DCR_BURST),
        Op::Write(S5PAR, TIM1 + DMAR),
        Op::Write(S5M0AR, ring),
        Op::Write(S5NDTR, RING_WORDS),
        Op::Write(S5FCR, 0),
        Op::Write(S5CR, S5CR_RUN | DMA_EN),
        Op::Write(TIM1 + DIER, UDE),
        Op::Write(TIM1 + CR1, CR1_STOPPED | CEN),
        // the tick's interrupt cleared TIM11's UIF on entry: still clear
        // after the copy means the count was this tick's
        Op::Sync {
            from: TIM11 + CNT,
            to: TIM1 + CNT,
            add: SYNC_CYCLES,
            limit: tick_len - 1,
            flag: TIM11 + SR,
            mask: 1,
        },
    ]
}
