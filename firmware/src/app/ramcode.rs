//! The handlers' code copied into SRAM and SRAM mapped at 0
//! (`polyturn_firmware::ramcode`, `memory.x`). Right after embassy's init,
//! which resets SYSCFG (its MEMRMP with it), and before anything calls
//! that code: nothing before it does (the DFU check, the priorities, the
//! init run from flash).

use embassy_stm32::pac;
use polyturn_firmware::ramcode::{sram_address, MEMRMP_SRAM, MPU_PROGRAM};

extern "C" {
    // memory.x: the section's addresses (in the alias at 0) and where its
    // load image starts in flash
    static __sramcode: u32;
    static __eramcode: u32;
    static __siramcode: u32;
}

/// Copies the code and maps SRAM at 0. Runs once, from flash.
pub fn map() {
    // (linker symbols: only their addresses mean anything, the section's
    // bounds)
    let (start, end, load) = (
        core::ptr::addr_of!(__sramcode) as u32,
        core::ptr::addr_of!(__eramcode) as u32,
        core::ptr::addr_of!(__siramcode),
    );
    let dst = sram_address(start) as *mut u32;
    for i in 0..((end - start) / 4) as usize {
        // SAFETY: the load image lies in flash and its copy in the first
        // RAMCODE_SIZE bytes of SRAM, which nothing else uses (memory.x)
        unsafe { dst.add(i).write_volatile(load.add(i).read_volatile()) };
    }
    // the copy complete before SRAM appears at 0 (PM0214 §2.2.4: DSB)
    cortex_m::asm::dsb();
    pac::RCC.apb2enr().modify(|w| w.set_syscfgen(true));
    cortex_m::asm::dsb();
    pac::SYSCFG.memrm().modify(|w| w.set_mem_mode(MEMRMP_SRAM as u8));
    // instructions fetched after the remap come from SRAM (PM0214 §2.2.4:
    // DSB then ISB after a change to the memory map)
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
    // the code read-only from here on (`MPU_PROGRAM`), with the same
    // barriers after the MPU's change (ARM DUI 0553A §4.5, "Updating an MPU
    // region")
    let _ = polyturn_firmware::regs::apply(&MPU_PROGRAM, &mut super::mmio::Mmio);
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}

/// Whether the code is in place: the panic and fault handlers run from
/// flash and call it only then.
pub fn mapped() -> bool {
    pac::SYSCFG.memrm().read().mem_mode() == MEMRMP_SRAM as u8
}
