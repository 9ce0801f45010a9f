//! The MCU half of `polyturn_firmware::dfu`: the console's `dfu` resets
//! into ST's ROM bootloader (USB DFU), with every output off first.

use core::mem::MaybeUninit;
use embassy_stm32::pac;
use polyturn_firmware::dfu;

/// The request word: in `.uninit` (cortex-m-rt leaves it as the reset
/// found it), so it survives the software reset that follows the request.
#[link_section = ".uninit.polyturn_dfu"]
static mut REQUEST: MaybeUninit<u32> = MaybeUninit::uninit();

fn request_word() -> *mut u32 {
    core::ptr::addr_of_mut!(REQUEST).cast::<u32>()
}

/// First thing at boot, before embassy's init: to the bootloader if `dfu`
/// asked for it, a reset if we came by the ROM's jump (`dfu::entry`), else
/// on with the application, whose vector table is made the one in force
/// (PM0214 §4.4.4 VTOR) and flash mapped at 0 again.
pub fn boot_check() {
    let csr = pac::RCC.csr().read().0;
    // SAFETY: nothing else runs yet; the word is read and cleared once.
    let word = unsafe { request_word().read_volatile() };
    unsafe { request_word().write_volatile(0) };
    pac::RCC.csr().modify(|w| w.set_rmvf(true));
    pac::RCC.apb2enr().modify(|w| w.set_syscfgen(true));
    // a peripheral's clock needs a moment before its registers take writes
    cortex_m::asm::dsb();
    match dfu::entry(word, csr) {
        // the flags are clear now: the reset sets SFTRSTF, the word is 0
        dfu::Entry::ResetFirst => cortex_m::peripheral::SCB::sys_reset(),
        dfu::Entry::Bootloader => {
            let table = dfu::SYSTEM_MEMORY as *const u32;
            // SAFETY: system memory is always readable (RM0383 §2.3).
            let (sp, reset) = unsafe { (table.read_volatile(), table.add(1).read_volatile()) };
            if dfu::plausible_vectors(sp, reset) {
                pac::SYSCFG.memrm().modify(|w| w.set_mem_mode(dfu::MEMRMP_SYSTEM_FLASH as u8));
                // SAFETY: the ROM's vector table, checked above; every
                // peripheral is as reset left it.
                unsafe { cortex_m::asm::bootload(table) }
            }
        }
        dfu::Entry::Application => {}
    }
    pac::SYSCFG.memrm().modify(|w| w.set_mem_mode(0));
    // SAFETY: our own vector table, at the start of flash (memory.x).
    unsafe { (*cortex_m::peripheral::SCB::PTR).vtor.write(0x0800_0000) };
}

/// After `dfu`'s reply: a moment for the host to read it, then every
/// output off, the request, and a reset.
pub async fn restart() -> ! {
    embassy_time::Timer::after_millis(100).await;
    // `dfu` was idle, but a key may have engaged meanwhile: ramp down
    // first (bounded: 2 s), then cut
    for _ in 0..200 {
        let idle = super::tick::with_core(|c| {
            c.disengage();
            c.state() == polyturn_sync::State::Idle
        });
        if idle != Some(false) {
            break;
        }
        embassy_time::Timer::after_millis(10).await;
    }
    cortex_m::interrupt::disable();
    super::drivers::all_outputs_off();
    // SAFETY: interrupts are off; the word is ours.
    unsafe { request_word().write_volatile(dfu::MAGIC) };
    cortex_m::peripheral::SCB::sys_reset()
}
