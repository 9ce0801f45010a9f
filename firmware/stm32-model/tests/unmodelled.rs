//! Configurations the model does not implement, or that the manual forbids, panic with
//! the register's address, so that firmware touching them is caught.
mod common;
use common::*;

const BUF: u32 = SRAM_BASE + 0x100;

#[test]
#[should_panic(expected = "not modelled")]
fn down_counting_is_refused() {
    mcu().write(TIM1_CR1, cr1::DIR.mask());
}

#[test]
#[should_panic(expected = "not modelled")]
fn center_aligned_mode_is_refused() {
    mcu().write(TIM1_CR1, cr1::CMS.val(1));
}

#[test]
#[should_panic(expected = "0x40010008")]
fn slave_mode_on_tim1_is_refused_with_its_address() {
    mcu().write(TIM1_SMCR, smcr::SMS.val(7));
}

#[test]
#[should_panic(expected = "not modelled")]
fn reserved_bits_must_stay_zero() {
    mcu().write(TIM1_CR1, 1 << 12);
}

// §9.5.5 EN: "Before setting EN bit to '1' to start a new transfer, the event flags
// corresponding to the stream in DMA_LISR or DMA_HISR register must be cleared."
#[test]
#[should_panic(expected = "flags still set")]
fn enabling_with_flags_set_is_refused() {
    let mut m = mcu();
    dma5(&mut m, TIM1_CCR2, BUF, 1, dma_cr::SIZE_HALF, false);
    m.write(TIM1_DIER, dier::UDE.mask());
    m.write(TIM1_EGR, egr::UG.mask());
    m.run_until(10);
    let cr = m.read(DMA2_S5CR);
    m.write(DMA2_S5CR, cr | dma_cr::EN.mask());
}

#[test]
#[should_panic(expected = "only ITR0")]
fn other_trigger_inputs_are_refused() {
    mcu().write(TIM2_SMCR, smcr::SMS.val(7) | smcr::TS.val(1));
}

#[test]
#[should_panic(expected = "0x400264a0")]
fn other_dma_streams_are_refused_with_their_address() {
    mcu().write(DMA2 + dma_off::sxcr(6), 0);
}

#[test]
#[should_panic(expected = "0x40000034")]
fn tim2_reads_of_unmodelled_registers_panic_too() {
    mcu().read(TIM2 + off::CCR1);
}
