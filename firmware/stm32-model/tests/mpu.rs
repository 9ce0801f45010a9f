//! The MPU program the firmware applies once its handlers' code is in SRAM
//! (`polyturn_firmware::ramcode::MPU_PROGRAM`), run through the model of the
//! Cortex-M4's MPU (ARM DUI 0553A §4.5): the code is read-only and
//! executable, at 0x2000_0000 and in its alias at 0, and everything the
//! firmware writes (its RAM, the step ring, the stack, the peripherals)
//! keeps the default map.

use polyturn_firmware::ramcode::{MPU_PROGRAM, RAMCODE_SIZE, SRAM_BASE};
use polyturn_firmware::regs::{apply, Bus};
use polyturn_stm32_model::chip::mpu::Access;
use polyturn_stm32_model::chip::nvic::Nvic;

/// The core's system space, the MPU's registers in it.
struct Ppb(Nvic);

impl Bus for Ppb {
    fn write(&mut self, addr: u32, value: u32) {
        assert!(addr >= 0xE000_0000, "{addr:#x}: not in the system space");
        self.0.write(addr - 0xE000_0000, value, u32::MAX, 0);
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.0.read(addr - 0xE000_0000, 0, &[], 0)
    }
    fn delay(&mut self, _: u32) {}
}

fn programmed() -> Nvic {
    let mut ppb = Ppb(Nvic::default());
    apply(&MPU_PROGRAM, &mut ppb).expect("the program completes");
    ppb.0
}

const CODE: Access = Access { read: true, write: false, fetch: true };
const ANY: Access = Access { read: true, write: true, fetch: true };

#[test]
fn the_handlers_code_is_read_only_and_runs_at_both_its_addresses() {
    let n = programmed();
    for off in (0..RAMCODE_SIZE).step_by(256).chain([RAMCODE_SIZE - 4]) {
        assert_eq!(n.mpu.access(SRAM_BASE + off), CODE, "{:#x}", SRAM_BASE + off);
        assert_eq!(n.mpu.access(off), CODE, "the alias at {off:#x}");
    }
}

#[test]
fn what_the_firmware_writes_keeps_the_default_map() {
    let n = programmed();
    // RAM after the code (memory.x), its last word (the stack's top), the
    // flash's interface and the peripherals, the system space
    for addr in [SRAM_BASE + RAMCODE_SIZE, 0x2001_FFFC, 0x0800_0000, 0x4001_0000, 0x4002_3C00, 0xE000_ED94] {
        assert_eq!(n.mpu.access(addr), ANY, "{addr:#x}");
    }
}

/// Every region the program enables is Normal memory, as the default map's
/// SRAM and code regions are (Table 4-45): code is fetched from Normal
/// memory only, and the regions change the access, not the memory type.
#[test]
fn the_regions_keep_the_memory_normal() {
    let n = programmed();
    let on: Vec<usize> = (0..8).filter(|&r| n.mpu.enabled(r)).collect();
    assert_eq!(on, vec![0, 1, 2, 3]);
    for r in on {
        assert!(n.mpu.normal(r), "region {r}: not Normal memory");
    }
}
