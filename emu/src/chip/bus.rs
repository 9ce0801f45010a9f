//! Bus accesses dispatched to the models. A byte or halfword access is a masked
//! access to its word (RM0383 §2.1: the APB peripherals take 8/16/32-bit accesses;
//! the timers, DMA and flash interface of [`Mcu`] only take words here).

use super::{Chip, Periph, SYSTEM_VECTORS, ZERO_READS};
use polyturn_stm32_model::chip::gpio::{ALTERNATE, MODER};
use polyturn_stm32_model::chip::gptimer::trigger;
use polyturn_stm32_model::chip::{exti, rcc};
use polyturn_sync::edges::EdgeRegs;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A model's "not modelled" panic as a message.
pub(super) fn caught<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|e| {
        e.downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default()
    })
}

impl Chip {
    /// Run TIM1/TIM2/TIM9/TIM11 and the DMA to CPU cycle `t`. They count at their
    /// kernel clock, which the model takes as SYSCLK's (true on this board: APB2
    /// undivided, APB1's timers at twice PCLK1, RM0383 §6.2).
    pub(super) fn mcu_run(&mut self, t: u64) {
        if t > self.mcu.cycle() {
            if let Err(e) = caught(|| self.mcu.run_until(t)) {
                self.fault(e);
            }
        }
    }

    fn mcu_clocks_ok(&self) -> bool {
        let s = self.sysclk();
        self.rcc.apb2().1 == s && self.rcc.apb1().1 == s
    }

    pub fn read(&mut self, addr: u32, size: u32) -> u32 {
        let word = addr & !3;
        let Some((base, p)) = self.find(word) else {
            if ZERO_READS.iter().any(|z| (z.0..z.1).contains(&addr)) {
                return 0;
            }
            if let Some(&(_, v)) = SYSTEM_VECTORS.iter().find(|w| w.0 == addr && size == 4) {
                return v;
            }
            self.fault(format!("read of {addr:#010x}: no model claims it"));
            return 0;
        };
        crate::chip::probe::on_read(self, word);
        self.sync();
        self.bus_wait(word, false);
        let off = word - base;
        let v = match p {
            Periph::Mcu if is_dmar(word) => self.narrow(addr, size),
            Periph::Mcu => caught(|| self.mcu.read(word)).unwrap_or_else(|e| {
                self.fault(e);
                0
            }),
            Periph::Rcc => self.rcc.read(off),
            Periph::Pwr => rcc::pwr_read(&self.pwr, &self.rcc, off),
            Periph::FlashIf => self.flash_read(word, off),
            Periph::Syscfg => self.syscfg.regs.get(off),
            Periph::Exti => self.exti.read(off),
            Periph::Gpio(i) => self.gpio[i].read(off),
            Periph::Gp(i) => self.gp[i].read(off),
            Periph::Iwdg => self.iwdg.read(off),
            Periph::Crc => self.crc.read(off),
            Periph::Usb => self.usb_read(off),
            Periph::Ppb => self.nvic.read(off, self.blk, &self.active, self.active.last().copied().unwrap_or(0) as u32),
        };
        self.tape_read(word, v);
        v >> (8 * (addr & 3)) & mask(size)
    }

    pub fn write(&mut self, addr: u32, size: u32, value: u32) {
        let word = addr & !3;
        let Some((base, p)) = self.find(word) else {
            self.fault(format!("write of {value:#x} to {addr:#010x}: no model claims it"));
            return;
        };
        self.sync();
        self.bus_wait(word, true);
        let (off, shift) = (word - base, 8 * (addr & 3));
        let (v, m) = (value << shift, mask(size) << shift);
        match p {
            Periph::Mcu if size != 4 && is_dmar(word) => {
                self.narrow(addr, size);
            }
            // a byte or halfword write is a word write of what the other lanes read
            // back: harmless for rc_w0 flags (writing back a 1 has no effect),
            // write-only registers (they read 0) and rc_w1 clears (they read 0)
            Periph::Mcu => {
                let merged = if size == 4 { value } else { self.mcu.read(word) & !m | v };
                self.mcu_write(word, merged)
            }
            Periph::Rcc => self.rcc.write(off, v, m),
            Periph::Pwr => self.pwr.write(off, v, m),
            Periph::FlashIf => self.flash_write(word, off, v, m),
            Periph::Syscfg => {
                self.syscfg.regs.write(off, v, m);
                if off == exti::MEMRMP {
                    self.mem_mode_written();
                }
            }
            Periph::Exti => self.exti.write(off, v, m),
            Periph::Gpio(i) => {
                let edges = self.gpio[i].write(off, v, m, self.blk);
                self.pin_edges(i, edges);
            }
            Periph::Gp(i) => self.gp[i].write(off, v, m),
            Periph::Iwdg => self.iwdg.write(off, v, m, self.blk),
            Periph::Crc => {
                if let Err(e) = caught(|| self.crc.write(off, v, m)) {
                    self.fault(e);
                }
            }
            Periph::Usb => self.usb_write(off, v, m),
            Periph::Ppb => self.nvic.write(off, v, m, self.blk),
        }
        crate::chip::probe::on_write(self, word, v);
    }

    /// SYSCFG_MEMRMP written (§7.2.1): system memory at 0 means the image is
    /// about to jump into ST's bootloader, which is not here, so the run
    /// ends; SRAM or flash at 0 changes what the CPU fetches there, which the
    /// machine maps between two runs (`Machine::remap`).
    fn mem_mode_written(&mut self) {
        match self.syscfg.at_zero() {
            exti::AtZero::SystemMemory => {
                self.rom_jump = true;
                self.fault("the image jumped to the ROM bootloader (system memory)".into());
            }
            exti::AtZero::Reserved => self.fault("SYSCFG_MEMRMP.MEM_MODE = 10: reserved on the F411 (§7.2.1)".into()),
            at if at != self.at_zero => self.remap = Some(at),
            _ => {}
        }
    }

    fn narrow(&mut self, addr: u32, size: u32) -> u32 {
        self.fault(format!("{size}-byte access at {addr:#010x}: TIMx_DMAR is modelled for 32-bit accesses only"));
        0
    }

    fn mcu_write(&mut self, word: u32, value: u32) {
        if !self.mcu_clocks_ok() {
            let f = format!("write to {word:#010x} while the timer clocks differ from SYSCLK: not modelled");
            self.fault(f);
            return;
        }
        if let Err(e) = caught(|| self.mcu.write(word, value)) {
            self.fault(e);
        }
    }

    /// Edges on port `port`'s pins go to EXTI (§10.2.3), and those of PA6, PA7 and
    /// PB0 to TIM3's TI1, TI2 and TI3 when the pins are in TIM3's alternate function
    /// (AF2, datasheet DS10314 table 9).
    pub fn pin_edges(&mut self, port: usize, edges: Vec<(u8, bool)>) {
        let mut tim3 = false;
        let pa4 = port == 0 && self.jumpers.index && edges.iter().any(|e| e.0 == 4);
        for (pin, rising) in edges {
            self.exti.edge(&self.syscfg, port as u32, pin, rising);
            tim3 |= matches!((port, pin), (0, 6) | (0, 7) | (1, 0));
        }
        if tim3 {
            let ti = |c: &Chip, port: usize, pin: u8| {
                let g = &c.gpio[port];
                g.field(MODER, pin) == ALTERNATE && g.afr(pin) == 2 && g.level(pin)
            };
            let levels = [ti(self, 0, 6), ti(self, 0, 7), ti(self, 1, 0)];
            self.gp[0].inputs(levels);
            self.tim3_trgo();
        }
        if pa4 {
            // the index jumper: PA4 (driven by software) to PB0 (TIM3_CH3)
            let level = self.gpio[0].level(4);
            let edges = self.gpio[1].drive(0, Some(level));
            self.pin_edges(1, edges);
        }
    }

    /// TIM3's TRGO to the timers whose ITR table row names it (TIM4 on ITR2,
    /// TIM5 on ITR1: RM0383 §13.4.3). Each CC1 capture goes on the tape with
    /// TIM5's count at that moment, the stamp the image must read (not
    /// TIM5_CCR3, which a wrong configuration would leave behind).
    fn tim3_trgo(&mut self) {
        use polyturn_stm32_model::addr::off::{CCR1, CNT};
        let [tim3, tim4, tim5, _] = &mut self.gp;
        let pulses = trigger::route("TIM3", tim3, &mut [("TIM4", tim4), ("TIM5", tim5)]);
        if let (true, Some(t)) = (pulses > 0, self.tape.as_mut()) {
            let regs = EdgeRegs { count: self.gp[0].get(CCR1) as u16, stamp: self.gp[2].read(CNT) as u16 };
            t.captures.push(crate::edge_times::Capture { at: self.blk, regs });
        }
    }

    /// FLASH_ACR and OPTCR as registers; KEYR, SR and CR are the erase model's.
    fn flash_read(&mut self, word: u32, off: u32) -> u32 {
        match off {
            0x04 | 0x0C | 0x10 => caught(|| self.flash.read(word)).unwrap_or_else(|e| {
                self.fault(e);
                0
            }),
            _ => self.flash_regs.get(off),
        }
    }

    fn flash_write(&mut self, word: u32, off: u32, v: u32, m: u32) {
        match off {
            0x04 | 0x0C | 0x10 => {
                let old = self.flash.read(word);
                let full = old & !m | v & m;
                if let Err(e) = caught(|| self.flash.write(word, full)) {
                    self.fault(e);
                }
                self.flash_erased();
            }
            _ => {
                self.flash_regs.write(off, v, m);
                if off == 0 {
                    // FLASH_ACR (§3.8.1): the wait states and caches from now
                    self.meter.set_acr(self.flash_regs.get(0));
                }
            }
        }
    }
}

/// TIMx_DMAR, whose access moves the DMA burst index (§12.4.20).
fn is_dmar(word: u32) -> bool {
    use polyturn_stm32_model::addr::{off, TIM1, TIM11, TIM2, TIM9};
    [TIM1, TIM2, TIM9, TIM11].iter().any(|b| word == b + off::DMAR)
}

fn mask(size: u32) -> u32 {
    if size >= 4 {
        u32::MAX
    } else {
        (1 << (8 * size)) - 1
    }
}

#[cfg(test)]
mod tests {
    use super::Chip;
    use polyturn_stm32_model::Params;

    #[test]
    fn only_the_bootloaders_vectors_read_from_system_memory_and_the_remap_ends_the_run() {
        let mut c = Chip::new(Params::default());
        let (sp, reset) = (c.read(0x1FFF_0000, 4), c.read(0x1FFF_0004, 4));
        assert!(polyturn_firmware::dfu::plausible_vectors(sp, reset), "{sp:#x} {reset:#x}");
        assert!(c.faults.is_empty());
        c.read(0x1FFF_0008, 4);
        assert_eq!(c.faults.len(), 1, "the rest of the ROM is no model's");
        let memrmp = crate::svd::base("SYSCFG");
        c.write(memrmp, 4, 0);
        assert!(!c.rom_jump, "flash at 0: the application's boot");
        c.write(memrmp, 4, polyturn_firmware::dfu::MEMRMP_SYSTEM_FLASH);
        assert!(c.rom_jump);
        assert!(c.faults[1].1.contains("ROM bootloader"), "{:?}", c.faults);
    }
}
