//! The emulated STM32F411: unicorn's Cortex-M4 core (Thumb, M-class), the memory
//! map (RM0383 §2.3: flash 512 KiB at 0x0800_0000, also aliased at 0 with BOOT0 = 0,
//! §2.4; SRAM 128 KiB at 0x2000_0000, which is the model's own SRAM so the DMA
//! reads what the CPU wrote), the peripheral bus, and time.
//!
//! Time: CPU cycles, on two clocks (`clock`): the model's, what silicon most
//! likely spends, on which the peripherals run, and the bound's, what it
//! cannot exceed. Each translated block's cost at zero wait states is
//! computed once from its instructions (`cycles`, the Cortex-M4 TRM's
//! timings) and cached; the flash's waits, taken branches, divisions,
//! exceptions and bus accesses are counted as they happen. An MMIO access
//! sees the time at the start of its block. The run is sliced: it stops at
//! the first block boundary at or after the next model event, where pending
//! interrupts are taken (`cpu.rs`).

pub mod commands;
pub mod cpu;
pub mod primask;

use crate::chip::Chip;
use crate::image::{Image, FLASH_BASE, FLASH_SIZE};
use polyturn_stm32_model::addr::{SRAM_BASE, SRAM_SIZE};
use polyturn_stm32_model::chip::exti::AtZero;
use polyturn_stm32_model::chip::{iwdg::LSI_HZ, rcc};
use polyturn_stm32_model::Params;
use std::rc::Rc;
use unicorn_engine::{Arch, HookType, Mode, Prot, RegisterARM, Unicorn};

/// Longest run between looks at the interrupt lines, in instructions.
const SLICE: u64 = 20_000;
const NOP: [u8; 2] = [0x00, 0xBF];

/// The flash as the board holds it: the image, its waits for events made
/// NOPs and sealed again over them, then `flash_init` (settings, or a
/// damage) written over it.
fn flashed(image: &Image, flash_init: &[(u32, Vec<u8>)]) -> Result<Box<[u8]>, String> {
    let mut flash = vec![0xFFu8; FLASH_SIZE as usize].into_boxed_slice(); // erased
    let put = |flash: &mut [u8], (addr, data): &(u32, Vec<u8>)| {
        let off = addr.wrapping_sub(FLASH_BASE) as usize;
        if off + data.len() > flash.len() {
            return Err(format!("a segment at {addr:#010x} lies outside the flash"));
        }
        flash[off..off + data.len()].copy_from_slice(data);
        Ok(())
    };
    for segment in &image.segments {
        put(&mut flash, segment)?;
    }
    // WFE, WFI and SEV are NOPs here: ARMv7-M ARM B1.5.18 lets WFE be a NOP, and
    // unicorn has none of them; time still passes through the loop around them
    for a in image.insns.wfe.iter().chain(&image.insns.sev).chain(&image.insns.wfi) {
        let Some(o) = a.checked_sub(FLASH_BASE).map(|o| o as usize) else {
            return Err(format!(
                "a wait for event at {a:#010x}, outside the flash: the emulator makes those NOPs only there"
            ));
        };
        flash[o..o + 2].copy_from_slice(&NOP);
    }
    // the image checks its own bytes at boot (`seal`): sealed again over the
    // NOPs, as if the image had been flashed so
    if let Some(at) = image.seal_at {
        crate::image::reseal(&mut flash, at);
    }
    // what was flashed besides (settings), or over it (a damaged image)
    for segment in flash_init {
        put(&mut flash, segment)?;
    }
    Ok(flash)
}

#[cfg(test)]
/// Thumb instructions in `code`: a halfword whose top five bits are 0b11101,
/// 0b11110 or 0b11111 starts a 32-bit instruction (ARMv7-M ARM A5.1).
pub fn insn_count(code: &[u8]) -> u64 {
    let (mut n, mut i) = (0, 0);
    while i + 1 < code.len() {
        let hw = u16::from_le_bytes([code[i], code[i + 1]]);
        i += if matches!(hw >> 11, 0x1D..=0x1F) { 4 } else { 2 };
        n += 1;
    }
    n
}

/// RCC_CSR's reset flags (RM0383 §6.3.21, bits 25-31), kept until RMVF.
const CSR_FLAGS: u32 = 0xFE00_0000;
const PINRSTF: u32 = 1 << 26;

/// Why the chip reset. Each also sets PINRSTF: an inference from the reset
/// circuit (§6.1.2: every internal reset source's pulse is output on NRST),
/// which the manual's PINRSTF text (§6.3.21, "a reset from the NRST pin")
/// does not state in so many words.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reset {
    /// SCB AIRCR.SYSRESETREQ: SFTRSTF
    Software,
    /// the independent watchdog: IWDGRSTF
    Watchdog { gap_ms: u64, timeout_ms: u64 },
    /// the NRST button
    Pin,
}

impl Reset {
    fn csr_flags(&self) -> u32 {
        PINRSTF
            | match self {
                Reset::Software => 1 << 28,
                Reset::Watchdog { .. } => 1 << 29,
                Reset::Pin => 0,
            }
    }
}

impl std::fmt::Display for Reset {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Reset::Software => write!(f, "the image asked for it (SCB AIRCR SYSRESETREQ)"),
            Reset::Watchdog { gap_ms, timeout_ms } => {
                write!(f, "the IWDG fired: no reload for {gap_ms} ms, over its shortest timeout {timeout_ms} ms")
            }
            Reset::Pin => write!(f, "NRST pressed (SIGUSR1)"),
        }
    }
}

pub struct Machine {
    pub uc: Unicorn<'static, Chip>,
    pub image: Rc<Image>,
    /// the lathe driving the encoder pins, when a job runs
    pub lathe: Option<crate::job::lathe::LatheDrive>,
    pub cpr: u32,
    params: Params,
    /// the flash as mapped (must outlive `uc`, declared after it)
    _flash: Box<[u8]>,
}

impl Machine {
    pub fn new(image: Rc<Image>, params: Params, flash_init: &[(u32, Vec<u8>)]) -> Result<Machine, String> {
        Machine::build(image, params, flash_init, true)
    }

    /// A machine for a bare-metal image (`bench`): without the hooks that
    /// follow the firmware's own functions (`tape`).
    pub fn bare(image: Rc<Image>) -> Result<Machine, String> {
        Machine::build(image, Params::default(), &[], false)
    }

    fn build(
        image: Rc<Image>,
        params: Params,
        flash_init: &[(u32, Vec<u8>)],
        firmware: bool,
    ) -> Result<Machine, String> {
        let mut flash = flashed(&image, flash_init)?;
        let mut chip = Chip::new(params);
        chip.meter = crate::clock::Meter::new(image.program.clone());
        chip.code = flash.to_vec();
        chip.flash_mem = flash.as_mut_ptr();
        let sram = chip.mcu.sram_mut_ptr();
        let mut uc = Unicorn::new_with_data(Arch::ARM, Mode::THUMB | Mode::MCLASS, chip)
            .map_err(|e| format!("unicorn: {e:?}"))?;
        let e = |r: Result<(), unicorn_engine::uc_error>| r.map_err(|e| format!("unicorn: {e:?}"));
        // SAFETY: both buffers live as long as `uc` (the flash in this struct, the SRAM
        // inside the chip `uc` owns) and are never reallocated
        unsafe {
            e(uc.mem_map_ptr(
                FLASH_BASE as u64,
                FLASH_SIZE as u64,
                Prot::READ | Prot::EXEC,
                flash.as_mut_ptr().cast(),
            ))?;
            e(uc.mem_map_ptr(0, FLASH_SIZE as u64, Prot::READ | Prot::EXEC, flash.as_mut_ptr().cast()))?;
            e(uc.mem_map_ptr(SRAM_BASE as u64, SRAM_SIZE as u64, Prot::ALL, sram.cast()))?;
        }
        for (base, size) in
            [(0x4000_0000u64, 0x8_0000u64), (0x5000_0000, 0x4_0000), (0xE000_0000, 0x10_0000), (0x1FFF_0000, 0x1_0000)]
        {
            let read = move |uc: &mut Unicorn<Chip>, off: u64, size: usize| {
                uc.get_data_mut().read((base + off) as u32, size as u32) as u64
            };
            let write = move |uc: &mut Unicorn<Chip>, off: u64, size: usize, v: u64| {
                uc.get_data_mut().write((base + off) as u32, size as u32, v as u32);
                crate::machine::cpu::after_write(uc);
                if uc.get_data().rom_jump || uc.get_data().remap.is_some() {
                    // stop before the jump's fetch from system memory, or
                    // the next fetch at 0 from the memory it maps there
                    let _ = uc.emu_stop();
                }
            };
            e(uc.mmio_map(base, size, Some(read), Some(write)))?;
        }
        let mut m = Machine { uc, image, lathe: None, cpr: 2400, params, _flash: flash };
        m.hooks()?;
        if firmware {
            crate::machine::commands::hooks(&mut m)?;
        }
        m.boot();
        Ok(m)
    }

    fn hooks(&mut self) -> Result<(), String> {
        let e = |r: Result<unicorn_engine::UcHookId, unicorn_engine::uc_error>| {
            r.map(|_| ()).map_err(|e| format!("unicorn: {e:?}"))
        };
        e(self.uc.add_block_hook(1, 0, |uc, addr, size| {
            let c = uc.get_data_mut();
            if c.now >= c.deadline {
                // stops before this block runs; the PC unicorn reports then can be the
                // previous block's start, so resume from here
                c.resume = Some(addr as u32);
                let _ = uc.emu_stop();
                return;
            }
            c.apply_fixups();
            c.begin_block(addr as u32, size);
            c.pc = addr as u32;
        }))?;
        e(self.uc.add_intr_hook(crate::machine::cpu::interrupt))?;
        let image = self.image.clone();
        e(self.uc.add_mem_hook(HookType::MEM_INVALID, 1, 0, move |uc, kind, addr, size, v| {
            let in_flash = (FLASH_BASE as u64..(FLASH_BASE + FLASH_SIZE) as u64).contains(&addr);
            if kind == unicorn_engine::MemType::WRITE_PROT && in_flash {
                // a store to flash: programming (or an error), not a bus fault
                uc.get_data_mut().flash_store(addr as u32, size as u32, v as u32);
                return true;
            }
            let pc = uc.reg_read(RegisterARM::PC).unwrap_or(0) as u32;
            let f = format!("bus fault: access to unmapped {addr:#010x} at pc {pc:#010x} ({})", image.func_at(pc));
            uc.get_data_mut().fault(f);
            false
        }))?;
        // the fault handlers and udf: reaching one is a failure
        let mut traps: Vec<(u32, String)> = [(3, "HardFault"), (4, "MemManage"), (5, "BusFault"), (6, "UsageFault")]
            .iter()
            .map(|&(n, what)| {
                let v = self.image.vectors[n] & !1;
                (v, format!("{what} handler reached ({})", self.image.func_at(v)))
            })
            .collect();
        traps.extend(
            self.image.insns.udf.iter().map(|&a| (a, format!("udf at {a:#010x} in {}", self.image.func_at(a)))),
        );
        for (a, text) in traps {
            e(self.uc.add_code_hook(a as u64, a as u64, move |uc, _, _| {
                uc.get_data_mut().fault(text.clone());
                let _ = uc.emu_stop();
            }))?;
        }
        self.divide_hooks()?;
        crate::machine::primask::hooks(self)
    }

    /// SDIV/UDIV take 2 to 12 cycles by their operands (`cycles::timing::divide`):
    /// the block's static cost holds the least, the rest is added as each runs.
    fn divide_hooks(&mut self) -> Result<(), String> {
        use crate::cycles::insn::Op;
        use crate::cycles::timing::{divide, DIVIDE_IN_BLOCK};
        let divs: Vec<(u32, bool, u8, u8)> = self
            .image
            .program
            .divides()
            .filter_map(|i| match i.op {
                Op::Div { signed, dividend, divisor } => Some((i.addr, signed, dividend, divisor)),
                _ => None,
            })
            .collect();
        for (a, signed, n, d) in divs {
            let reg = |r: u8| RegisterARM::R0 as i32 + r as i32;
            // (code in flash runs at its address; linked below it, SRAM at 0)
            let alias = a.checked_sub(FLASH_BASE);
            for at in std::iter::once(a).chain(alias) {
                self.uc
                    .add_code_hook(at as u64, at as u64, move |uc, _, _| {
                        let (n, d) = (uc.reg_read(reg(n)).unwrap_or(0) as u32, uc.reg_read(reg(d)).unwrap_or(0) as u32);
                        let c = divide(n, d, signed);
                        let chip = uc.get_data_mut();
                        chip.now += c.model.saturating_sub(DIVIDE_IN_BLOCK.model) as u64;
                        chip.bound += c.bound.saturating_sub(DIVIDE_IN_BLOCK.bound) as u64;
                    })
                    .map_err(|e| format!("unicorn: {e:?}"))?;
            }
        }
        Ok(())
    }

    /// Maps at 0 what SYSCFG_MEMRMP chose (§7.2.1): the flash, as at reset,
    /// or the SRAM, the same bytes the CPU reads at 0x2000_0000.
    fn remap(&mut self, at: AtZero) {
        let (ptr, size) = match at {
            AtZero::Sram => (self.chip().mcu.sram_mut_ptr(), SRAM_SIZE),
            _ => (self._flash.as_mut_ptr(), FLASH_SIZE),
        };
        let now = if self.chip().at_zero == AtZero::Sram { SRAM_SIZE } else { FLASH_SIZE };
        let done = self.uc.mem_unmap(0, now as u64).and_then(|_| {
            // SAFETY: as in `new`: the flash is this struct's and the SRAM
            // its chip's, neither reallocated while `uc` lives
            unsafe { self.uc.mem_map_ptr(0, size as u64, Prot::READ | Prot::EXEC, ptr.cast()) }
        });
        match done {
            Ok(()) => {
                self.chip().at_zero = at;
                self.chip().meter.set_sram_at_zero(at == AtZero::Sram);
            }
            Err(e) => self.chip().fault(format!("unicorn: remapping address 0: {e:?}")),
        }
    }

    fn boot(&mut self) {
        let (sp, rv) = (self.image.vectors[0], self.image.vectors[1]);
        let _ = self.uc.reg_write(RegisterARM::SP, sp as u64);
        let _ = self.uc.reg_write(RegisterARM::PC, rv as u64);
    }

    /// A power cycle: a new machine from the flash as this one left it; RAM,
    /// registers and time start again (a reset that keeps the SRAM, as the
    /// reset pin or SYSRESETREQ does, is `reset_as`).
    pub fn reset(mut self) -> Result<Machine, String> {
        self.chip().apply_fixups();
        let flash = self._flash.to_vec();
        Machine::new(self.image.clone(), self.params, &[(FLASH_BASE, flash)])
    }

    /// A system reset (RM0383 §6.1.2) of this machine: the flash and the SRAM
    /// keep their contents (only a power-on loses the SRAM, and cortex-m-rt's
    /// `.uninit` relies on that), the registers and the CPU's cycle count start
    /// again, RCC_CSR shows why (§6.3.21), and whatever drives the pins from
    /// outside (the E-stop, the lathe's encoder) goes on driving them.
    pub fn reset_as(mut self, why: &Reset) -> Result<Machine, String> {
        self.chip().apply_fixups();
        let flash = self._flash.to_vec();
        let sram = self.chip().mcu.sram_mut_ptr();
        let mut m = Machine::new(self.image.clone(), self.params, &[(FLASH_BASE, flash)])?;
        // SAFETY: both SRAMs are SRAM_SIZE bytes, owned by two distinct chips
        unsafe { std::ptr::copy_nonoverlapping(sram, m.chip().mcu.sram_mut_ptr(), SRAM_SIZE as usize) };
        let old = self.chip().rcc.regs.get(rcc::CSR) & CSR_FLAGS;
        let regs = &mut m.chip().rcc.regs;
        regs.set(rcc::CSR, (regs.get(rcc::CSR) & !CSR_FLAGS) | old | why.csr_flags());
        for port in 0..3 {
            for pin in 0..16 {
                let level = self.chip().gpio[port].external(pin);
                if level.is_some() {
                    m.drive(port, pin, level);
                }
            }
        }
        let now = self.chip().now;
        m.cpr = self.cpr;
        m.lathe = self.lathe.take().map(|mut l| {
            l.rebase(now);
            l
        });
        Ok(m)
    }

    /// A reset the chip makes by itself, if one is due: the image asked for it
    /// (SCB AIRCR.SYSRESETREQ, PM0214 §4.4.5), or the watchdog ran out (§15.3:
    /// its countdown from the last reload, at the LSI's fastest, so its
    /// shortest timeout, the bound `checks` holds every gap to).
    pub fn reset_due(&mut self) -> Option<Reset> {
        let c = self.chip();
        if c.nvic.reset_requested {
            return Some(Reset::Software);
        }
        let (at, timeout_ns) = c.iwdg.last_reload(LSI_HZ[2])?;
        let gap_ns = (c.now - at) * 1_000_000_000 / c.sysclk();
        (gap_ns > timeout_ns)
            .then_some(Reset::Watchdog { gap_ms: gap_ns / 1_000_000, timeout_ms: timeout_ns / 1_000_000 })
    }

    pub fn chip(&mut self) -> &mut Chip {
        self.uc.get_data_mut()
    }

    pub fn pc(&self) -> u32 {
        self.uc.reg_read(RegisterARM::PC).unwrap_or(0) as u32
    }

    /// A `u32` static of the image, by a part of its mangled name (e.g.
    /// `9telemetry10TICKS_LOST17h`); `None` if the image has no such symbol.
    pub fn static_u32(&self, name: &str) -> Option<u32> {
        let addr = self.image.symbols.iter().find(|(n, _)| n.contains(name)).map(|(_, &a)| a)?;
        let mut word = [0u8; 4];
        self.uc.mem_read(addr as u64, &mut word).ok().map(|_| u32::from_le_bytes(word))
    }

    /// The clock the image measured at its start and gave its core (its
    /// `app::tick::watch::EDGE_CLOCK`: the first instant, k0 mod 4 at bit 16, on at
    /// bit 18), and k0 mod 4; `None` if it times no edges.
    pub fn edge_clock(&self) -> Option<(polyturn_sync::edges::EdgeClock, u16)> {
        let v = self.static_u32("5watch10EDGE_CLOCK17h")?;
        let k0 = (v >> 16 & 3) as u16;
        let per_tick = polyturn_firmware::edgetime::STAMPS_PER_TICK;
        let clock = polyturn_sync::edges::EdgeClock {
            first_instant: v as u16,
            stamps_per_tick: per_tick,
            low_low_odd: k0 & 1 == 1,
        };
        (v >> 18 & 1 == 1).then_some((clock, k0))
    }

    /// Run `cycles` more CPU cycles (or until a fault).
    pub fn run(&mut self, cycles: u64) {
        let end = self.chip().now + cycles;
        while self.chip().now < end && self.chip().faults.is_empty() {
            self.chip().sync_to_now();
            self.lathe_edges();
            crate::machine::cpu::take(self);
            let now = self.chip().now;
            let lathe = self.lathe.as_mut().and_then(|l| l.next_edge(now + SLICE)).unwrap_or(u64::MAX);
            let c = self.chip();
            let next = c.next_event().unwrap_or(u64::MAX).min(lathe);
            c.deadline = end.min(c.now + SLICE).min(next);
            c.blk = c.now;
            c.resume = None;
            let pc = self.pc();
            if let Err(err) = self.uc.emu_start((pc | 1) as u64, 0xFFFF_FFFF, 0, 0) {
                if self.chip().faults.is_empty() {
                    let f = format!("unicorn: {err:?} at {pc:#010x} ({})", self.image.func_at(self.pc()));
                    self.chip().fault(f);
                }
            }
            if let Some(r) = self.chip().resume.filter(|_| self.chip().faults.is_empty()) {
                let _ = self.uc.reg_write(RegisterARM::PC, (r | 1) as u64);
            }
            if let Some(at) = self.chip().remap.take() {
                self.remap(at);
            }
        }
        self.chip().sync_to_now();
    }

    /// The encoder's edges due by now, onto PA6, PA7 and PB0.
    fn lathe_edges(&mut self) {
        let now = self.chip().now;
        while let Some(c) = self.lathe.as_mut().and_then(|l| l.take_due(now)) {
            let [a, b, z] = crate::job::lathe::levels(c, self.cpr);
            self.drive(0, 6, Some(a));
            self.drive(0, 7, Some(b));
            self.drive(1, 0, Some(z));
        }
    }

    /// Drive input pin `pin` of port `port` (0 = A) from outside; `None` floats it.
    pub fn drive(&mut self, port: usize, pin: u8, level: Option<bool>) {
        let c = self.chip();
        c.sync_to_now();
        let edges = c.gpio[port].drive(pin, level);
        c.pin_edges(port, edges);
        crate::machine::cpu::after_write(&mut self.uc);
    }
}

#[cfg(test)]
mod tests {
    use super::insn_count;

    #[test]
    fn a_32_bit_instruction_counts_once() {
        // movs r0, #1 (16-bit); bl (32-bit: 0xF000 0xF800); bx lr (16-bit)
        let code = [0x01, 0x20, 0x00, 0xF0, 0x00, 0xF8, 0x70, 0x47];
        assert_eq!(insn_count(&code), 3);
        // ldr.w (0xF8D0 ...): 0b11111 prefix
        assert_eq!(insn_count(&[0xD0, 0xF8, 0x00, 0x00]), 1);
    }

    #[test]
    fn every_reset_shows_the_pin_and_its_own_flag() {
        use super::Reset;
        let w = Reset::Watchdog { gap_ms: 6000, timeout_ms: 5446 };
        assert_eq!(Reset::Software.csr_flags(), 1 << 28 | 1 << 26, "SFTRSTF: what `dfu` checks");
        assert_eq!(w.csr_flags(), 1 << 29 | 1 << 26, "IWDGRSTF");
        assert_eq!(Reset::Pin.csr_flags(), 1 << 26, "PINRSTF alone: NRST, never the bootloader");
        assert!(w.to_string().starts_with("the IWDG fired"), "{w}");
    }
}
