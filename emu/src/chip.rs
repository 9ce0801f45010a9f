//! The STM32F411CE as the firmware sees it: every model at its SVD base address.
//! TIM1, TIM2, TIM9, TIM11 and DMA2 stream 5 are the cycle-exact [`Mcu`]; the rest
//! are `polyturn_stm32_model::chip`'s event-driven models. An access to an address
//! no model claims stops the run with its address and the function it came from,
//! except the short list in [`ZERO_READS`].

mod bus;
mod flashmem;
mod lines;
pub mod pins;
pub mod probe;
pub mod tape;
mod usb;

use crate::svd;
use polyturn_stm32_model::chip::{
    crc::Crc, exti, gpio::Port, gptimer::GpTimer, iwdg::Iwdg, nvic::Nvic, otg::Otg, rcc, RegFile,
};
use polyturn_stm32_model::flash::{EraseTime, Flash};
use polyturn_stm32_model::{Mcu, Params};

/// Reads that answer 0 without a model, each with why it is harmless: the ROM's
/// unique ID and flash-size words (RM0383 §24.1, §24.2), which only name the board.
pub const ZERO_READS: &[(u32, u32, &str)] = &[(0x1FFF_7A10, 0x1FFF_7A24, "unique ID and flash size (§24)")];

/// ST's ROM bootloader is not here: only its first two words, the vector table
/// at the start of system memory (RM0383 §2.3) that the image reads before it
/// jumps there (`firmware/src/app/dfu.rs`), answer, with a stand-in of the shape
/// `dfu::plausible_vectors` checks (a stack in SRAM, a Thumb reset handler in
/// system memory). The jump itself stops the run: see [`Chip::rom_jump`].
pub const SYSTEM_VECTORS: [(u32, u32); 2] = [(0x1FFF_0000, 0x2000_3000), (0x1FFF_0004, 0x1FFF_0201)];

/// The peripherals on the bus, in the order of `Chip::map`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Periph {
    Mcu,
    Rcc,
    Pwr,
    FlashIf,
    Syscfg,
    Exti,
    Gpio(usize),
    Gp(usize),
    Iwdg,
    Crc,
    Usb,
    Ppb,
}

pub struct Chip {
    pub mcu: Mcu,
    pub rcc: rcc::Rcc,
    pub pwr: RegFile,
    pub flash_regs: RegFile,
    pub flash: Flash,
    flash_ns: (u64, u64),
    pub syscfg: exti::Syscfg,
    pub exti: exti::Exti,
    /// GPIOA, GPIOB, GPIOC
    pub gpio: [Port; 3],
    /// TIM3, TIM4, TIM5, TIM10
    pub gp: [GpTimer; 4],
    pub iwdg: Iwdg,
    /// the CRC unit, with which the image checks itself at boot (`seal`)
    pub crc: Crc,
    pub usb: Otg,
    /// the emulated USB host on the cable, when a scenario plugs one in
    pub host: Option<Box<crate::usb::host::Host>>,
    pub nvic: Nvic,
    map: Vec<(u32, u32, Periph)>,
    /// CPU cycles so far on the model's clock (`clock`: the peripherals run on
    /// it), and at the start of the block running now (what an MMIO access sees)
    pub now: u64,
    pub blk: u64,
    /// the same on the bound's clock
    pub bound: u64,
    pub blk_bound: u64,
    /// the block running now: (address, size)
    pub block: (u32, u32),
    /// the cycles each block, exception and bus access costs (`clock`)
    pub meter: crate::clock::Meter,
    /// DMA2's transfers already counted in the bound, and the CPU's APB2
    /// accesses since (`dma_in_bound`)
    dma_seen: u64,
    apb2_accesses: u64,
    /// where each exception's cycles go, block by block (`--profile`)
    pub profile: Option<crate::clock::profile::Profile>,
    pub faults: Vec<(u64, String)>,
    /// exceptions being handled, outermost first
    pub active: Vec<usize>,
    /// the function the current block is in (for messages), set by the machine
    pub pc: u32,
    /// the run stops at the first block boundary at or after this cycle
    pub deadline: u64,
    /// where to resume after a stop at a block boundary
    pub resume: Option<u32>,
    /// the flash's bytes as mapped
    pub code: Vec<u8>,
    /// times each exception was entered, by number
    pub entries: std::collections::HashMap<usize, u64>,
    pub probe: crate::chip::probe::Probe,
    /// the flash array's bytes (the machine's), stores waiting to be put right,
    /// erases applied to them, and CPU cycles stalled by flash operations
    pub flash_mem: *mut u8,
    pub fixups: Vec<flashmem::Fixup>,
    erases_applied: usize,
    pub stalled: u64,
    /// the bench self-test's jumpers: PA2-PA6 and PA3-PA7 (`ab`), PA4-PB0 (`index`)
    pub jumpers: Jumpers,
    /// TIM1/TIM9 pin edges already passed through the jumpers
    mcu_edges_seen: usize,
    pub primask: crate::sections::SectionLog,
    /// the sections that hold off the tick (`tickmask`)
    pub tickmask: crate::sections::SectionLog,
    /// the tick's inputs and ENABLE, recorded when a job asks (`tape`)
    pub tape: Option<crate::chip::tape::Tape>,
    /// until this cycle the tick is held off as a thread-mode section at its
    /// level would hold it (`lines::deliverable`): a job's lost tick
    pub tick_held_until: u64,
    /// a job's hold on the step plan's level alone (`job::planlate`)
    pub plan_held_until: u64,
    /// the image mapped system memory at 0 (SYSCFG_MEMRMP.MEM_MODE = 01, §7.2.1)
    /// to jump to the ROM bootloader, which this emulator does not have
    pub rom_jump: bool,
    /// what the CPU sees at 0 now, and a change the image asked for that the
    /// machine makes between two runs (SYSCFG_MEMRMP, §7.2.1)
    pub at_zero: exti::AtZero,
    pub remap: Option<exti::AtZero>,
}

pub const GP_NAMES: [&str; 4] = ["TIM3", "TIM4", "TIM5", "TIM10"];

/// Wires on the bench between pins (`polyturn device selftest`'s jumpers).
#[derive(Clone, Copy, Debug, Default)]
pub struct Jumpers {
    pub ab: bool,
    pub index: bool,
}

impl Chip {
    pub fn new(params: Params) -> Chip {
        let mut map = vec![
            (polyturn_stm32_model::addr::TIM1, 0x400, Periph::Mcu),
            (polyturn_stm32_model::addr::TIM2, 0x400, Periph::Mcu),
            (polyturn_stm32_model::addr::TIM9, 0x400, Periph::Mcu),
            (polyturn_stm32_model::addr::TIM11, 0x400, Periph::Mcu),
            (polyturn_stm32_model::addr::DMA2, 0x400, Periph::Mcu),
            (svd::base("RCC"), 0x400, Periph::Rcc),
            (svd::base("PWR"), 0x400, Periph::Pwr),
            (svd::base("FLASH"), 0x400, Periph::FlashIf),
            (svd::base("SYSCFG"), 0x400, Periph::Syscfg),
            (svd::base("EXTI"), 0x400, Periph::Exti),
            (svd::base("IWDG"), 0x400, Periph::Iwdg),
            (svd::base("CRC"), 0x400, Periph::Crc),
            (svd::base("USB_OTG_FS"), 0x4_0000, Periph::Usb),
            (0xE000_0000, 0x10_0000, Periph::Ppb),
        ];
        for (i, p) in ["GPIOA", "GPIOB", "GPIOC"].iter().enumerate() {
            map.push((svd::base(p), 0x400, Periph::Gpio(i)));
        }
        for (i, t) in GP_NAMES.iter().enumerate() {
            map.push((svd::base(t), 0x400, Periph::Gp(i)));
        }
        map.sort_by_key(|m| m.0);
        // TIM3/TIM4 16-bit, TIM5 32-bit (§13.1), TIM10 one channel (§14.1)
        let mut gp = [GpTimer::new(16, 4), GpTimer::new(16, 4), GpTimer::new(32, 4), GpTimer::new(16, 1)];
        gp[0].set_encoder_capture(params.encoder_capture);
        Chip {
            mcu: Mcu::new(params),
            rcc: rcc::Rcc::default(),
            pwr: rcc::pwr_reset(),
            // §3.8.7: FLASH_OPTCR resets to 0x0FFF_AAED
            flash_regs: RegFile::new(&[(0x14, 0x0FFF_AAED)]),
            flash: Flash::new(EraseTime::Typical),
            flash_ns: (0, 0),
            syscfg: exti::Syscfg::default(),
            exti: exti::Exti::default(),
            gpio: [Port::new('A'), Port::new('B'), Port::new('C')],
            gp,
            iwdg: Iwdg::default(),
            crc: Crc::default(),
            usb: Otg::default(),
            host: None,
            nvic: Nvic::default(),
            map,
            now: 0,
            blk: 0,
            bound: 0,
            blk_bound: 0,
            block: (0, 0),
            meter: crate::clock::Meter::new(Default::default()),
            dma_seen: 0,
            apb2_accesses: 0,
            profile: None,
            tick_held_until: 0,
            plan_held_until: 0,
            faults: Vec::new(),
            active: Vec::new(),
            pc: 0,
            deadline: 0,
            resume: None,
            code: Vec::new(),
            entries: Default::default(),
            probe: Default::default(),
            flash_mem: std::ptr::null_mut(),
            fixups: Vec::new(),
            erases_applied: 0,
            stalled: 0,
            jumpers: Jumpers::default(),
            mcu_edges_seen: 0,
            primask: Default::default(),
            tickmask: Default::default(),
            tape: None,
            rom_jump: false,
            at_zero: exti::AtZero::Flash,
            remap: None,
        }
    }

    pub fn sysclk(&self) -> u64 {
        self.rcc.sysclk()
    }

    /// The kernel clock of general-purpose timer `i`: TIM3/4/5 on APB1, TIM10 on APB2.
    fn gp_clk(&self, i: usize) -> u64 {
        if i == 3 {
            self.rcc.apb2().1
        } else {
            self.rcc.apb1().1
        }
    }

    /// Every time-dependent model brought to the time an access in this block sees.
    pub fn sync(&mut self) {
        self.apply_fixups();
        let t = self.blk;
        let sysclk = self.sysclk();
        for i in 0..4 {
            let clk = self.gp_clk(i);
            self.gp[i].advance(t, sysclk, clk);
        }
        self.mcu_run(t);
        self.dma_in_bound();
        self.note_first_tick();
        if self.jumpers.ab {
            self.wire_ab();
        }
        // the flash interface keeps nanoseconds: cycles at the clock of the moment
        let (at, ns) = self.flash_ns;
        let ns = ns + (t - at) * 1_000_000_000 / sysclk;
        self.flash_ns = (t, ns);
        let d = ns.saturating_sub(self.flash.now_ns());
        self.flash.advance_ns(d);
        // a flag raised while time moved is latched as pending now (PM0214 §4.3.9),
        // even if the access that follows clears it
        self.update_lines();
    }

    /// TIM5's count at TIM11's first update event (the first tick's instant),
    /// for the tape: time has just been brought to the first block boundary at
    /// or after it (the update is an event the run stops at).
    fn note_first_tick(&mut self) {
        let Some(t) = self.tape.as_mut() else { return };
        if t.first_update_stamp.is_none() && self.mcu.tim11_updates() > 0 {
            t.first_update_stamp = Some(self.gp[2].read(polyturn_stm32_model::addr::off::CNT) as u16);
        }
    }

    /// TIM9's outputs on PA2/PA3 reach PA6/PA7 through the jumpers, edge by edge
    /// in the order the model made them (TIM3 counts transitions, not time).
    fn wire_ab(&mut self) {
        use polyturn_stm32_model::PinId;
        let new: Vec<(u8, bool)> = self.mcu.edges()[self.mcu_edges_seen..]
            .iter()
            .filter_map(|e| match e.pin {
                PinId::Pa2 => Some((6, e.high)),
                PinId::Pa3 => Some((7, e.high)),
                _ => None,
            })
            .collect();
        self.mcu_edges_seen = self.mcu.edges().len();
        for (pin, high) in new {
            let edges = self.gpio[0].drive(pin, Some(high));
            self.pin_edges(0, edges);
        }
    }

    /// The next CPU cycle at which a model raises a flag, if any.
    pub fn next_event(&self) -> Option<u64> {
        let sysclk = self.sysclk();
        let gp = (0..4).filter_map(|i| self.gp[i].next_event(sysclk, self.gp_clk(i)));
        let quiet = self.mcu.quiet_cycles();
        let mcu = (quiet < u64::MAX / 2).then(|| self.mcu.cycle() + quiet.max(1));
        // (the end of a hold: the held tick is taken then, not at the next event)
        let held = (self.now < self.tick_held_until).then_some(self.tick_held_until);
        let plan_held = (self.now < self.plan_held_until).then_some(self.plan_held_until);
        gp.chain(mcu).chain(self.usb_next()).chain(held).chain(plan_held).min()
    }

    pub fn fault(&mut self, text: String) {
        self.faults.push((self.now, text));
        self.deadline = 0;
    }

    /// Models brought to the end of the last block (between runs).
    pub fn sync_to_now(&mut self) {
        self.blk = self.now;
        self.sync();
        self.usb_step();
    }

    /// The block of `size` bytes at `addr` starts now: both clocks moved to
    /// its first instruction, and on by its cost (`clock::Meter::block`).
    pub fn begin_block(&mut self, addr: u32, size: u32) {
        let (lead, body) = self.meter.block(addr, size, self.now, self.bound);
        if let Some(p) = self.profile.as_mut().filter(|p| p.window.contains(&self.now)) {
            p.add(self.active.last().copied().unwrap_or(0), addr, lead + body);
        }
        self.now += lead.model as u64;
        self.bound += lead.bound as u64;
        (self.blk, self.blk_bound, self.block) = (self.now, self.bound, (addr, size));
        self.probe.trail_block(self.blk, self.blk_bound);
        self.now += body.model as u64;
        self.bound += body.bound as u64;
    }

    /// A bus access's wait on both clocks (`clock::bus`).
    pub(crate) fn bus_wait(&mut self, addr: u32, write: bool) {
        use crate::clock::bus;
        let b = bus::bus_of(addr);
        let hclk = self.sysclk();
        let pclk = match b {
            bus::Bus::Apb1 => self.rcc.apb1().0,
            bus::Bus::Apb2 => self.rcc.apb2().0,
            _ => hclk,
        };
        let c = bus::access(b, hclk / pclk.max(1), write);
        if b == bus::Bus::Apb2 {
            self.apb2_accesses += 1;
        }
        self.now += c.model as u64;
        self.bound += c.bound as u64;
    }

    /// DMA2's transfers since the last look, in the bound: each reads the
    /// SRAM the CPU fetches its code from and keeps its data in, and writes
    /// TIM1 on APB2 (RM0383 §2.1, the bus matrix arbitrates each slave
    /// between its masters round-robin): it can hold the CPU off the SRAM
    /// for its read (a cycle, and one of arbitration) every time, and off
    /// APB2 for its write only as often as the CPU went there meanwhile.
    fn dma_in_bound(&mut self) {
        let n = self.mcu.dma_transfers();
        let new = n - self.dma_seen.min(n);
        self.dma_seen = n;
        let apb2 = crate::clock::bus::access(crate::clock::bus::Bus::Apb2, 1, true).bound as u64 + 1;
        let met = new.min(std::mem::take(&mut self.apb2_accesses));
        self.bound += new * 2 + met * apb2;
    }

    pub fn find(&self, addr: u32) -> Option<(u32, Periph)> {
        let i = self.map.partition_point(|m| m.0 <= addr);
        let (base, size, p) = *self.map.get(i.checked_sub(1)?)?;
        (addr < base + size).then_some((base, p))
    }
}
