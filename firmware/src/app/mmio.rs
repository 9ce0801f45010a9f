//! The registers and RAM as the MCU sees them: the one `Bus` the register
//! programs (`stepgen`, `edgetime`, `bldcout`, `quadgen`, `flashprog`,
//! `seal`) are applied to on the chip, and the only place they touch
//! hardware. Its own room, so that every driver can take it without taking
//! the others.

use polyturn_firmware::stepgen::program::Bus;

/// The MCU's bus: word writes and reads at their addresses.
pub struct Mmio;

impl Bus for Mmio {
    fn write(&mut self, addr: u32, value: u32) {
        // SAFETY: the register programs (`stepgen::program`, `flashprog`,
        // `quadgen::program`, `edgetime`, `bldcout`, `seal`) name only
        // TIM1, TIM2, TIM3, TIM5, TIM9, TIM10, TIM11, DMA2, FLASH, CRC,
        // RCC_AHB1ENR, GPIOA/GPIOC MODER and BSRR, GPIOA_IDR registers
        // (RM0383 §2.3), DEMCR and the DWT's CTRL and CYCCNT (PM0214
        // §4.1), the flash's image (read) and the step output's DMA ring
        // (`drivers::RING`), all word-aligned.
        unsafe { (addr as *mut u32).write_volatile(value) }
    }
    fn read(&mut self, addr: u32) -> u32 {
        // SAFETY: as for `write`.
        unsafe { (addr as *const u32).read_volatile() }
    }
    fn delay(&mut self, cycles: u32) {
        // the timers run at the CPU clock (board::SYSCLK_HZ)
        cortex_m::asm::delay(cycles);
    }
    fn barrier(&mut self) {
        cortex_m::asm::dmb();
    }
}
