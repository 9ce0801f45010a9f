//! Helpers shared by the integration tests: register writes built from `bits`.
#![allow(dead_code)]

pub use polyturn_stm32_model::addr::*;
pub use polyturn_stm32_model::bits::*;
#[allow(unused_imports)]
pub use polyturn_stm32_model::{Edge, Mcu, NdtrReading, Params, PinId, PwmModeSwitch};

pub fn mcu() -> Mcu {
    Mcu::new(Params::default())
}

pub fn steps(m: &mut Mcu, n: u64) {
    for _ in 0..n {
        m.step();
    }
}

/// TIM1 CNT after each of the next `n` cycles.
pub fn cnt_trace(m: &mut Mcu, n: usize) -> Vec<u32> {
    (0..n)
        .map(|_| {
            m.step();
            m.read(TIM1_CNT)
        })
        .collect()
}

/// Channel 1 of TIM1 in `mode` with OC1 driven on PA8 (CC1E, MOE), no preloads.
pub fn tim1_ch1(m: &mut Mcu, arr: u32, ccr1: u32, mode: u32) {
    m.write(TIM1_ARR, arr);
    m.write(TIM1_CCR1, ccr1);
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(mode));
    m.write(TIM1_CCER, ccer::cce(0).mask());
    m.write(TIM1_BDTR, bdtr::MOE.mask());
}

pub fn start_tim1(m: &mut Mcu, extra_cr1: u32) {
    m.write(TIM1_CR1, cr1::CEN.mask() | extra_cr1);
}

pub fn uif1(m: &mut Mcu) -> bool {
    sr::UIF.on(m.read(TIM1_SR))
}

/// DMA2 stream 5 for TIM1_UP: memory `mem` to peripheral `par`, `n` items of `size`
/// (dma_cr::SIZE_HALF or SIZE_WORD), MINC, optional CIRC, then enabled.
pub fn dma5(m: &mut Mcu, par: u32, mem: u32, n: u32, size: u32, circ: bool) {
    m.write(DMA2_S5PAR, par);
    m.write(DMA2_S5M0AR, mem);
    m.write(DMA2_S5NDTR, n);
    let cr = dma_cr::CHSEL.val(6)
        | dma_cr::DIR.val(dma_cr::DIR_M2P)
        | dma_cr::MINC.mask()
        | dma_cr::PSIZE.val(size)
        | dma_cr::MSIZE.val(size)
        | dma_cr::CIRC.val(circ as u32);
    m.write(DMA2_S5CR, cr);
    m.write(DMA2_S5CR, cr | dma_cr::EN.mask());
}

/// Half-words stored little-endian from `at`, two per 32-bit write.
pub fn sram_u16(m: &mut Mcu, at: u32, data: &[u16]) {
    for (i, pair) in data.chunks(2).enumerate() {
        let hi = pair.get(1).copied().unwrap_or(0) as u32;
        m.write(at + 4 * i as u32, pair[0] as u32 | hi << 16);
    }
}
