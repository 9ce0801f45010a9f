//! The firmware's step output on the peripheral model: the real sync core,
//! the firmware's `stepgen` (its register programs and DMA ring, byte for
//! byte) and `polyturn-stm32-model`, the model written from RM0383 (TIM1,
//! TIM2, TIM9, TIM11, DMA2, TIM3's encoder interface and the flash's sector
//! erase; the step output uses TIM1, TIM2, TIM11 and DMA2). A control tick
//! runs at TIM11's update plus an interrupt latency drawn from a range; the
//! pins' edges are judged by a stepper driver's rules (`driver`). The sweep
//! of steady rates and lathe motions is `scenarios`.

pub mod driver;
pub mod latches;
pub mod scenarios;
pub mod steady_lathe;

use polyturn_firmware::stepgen::program::{self as prog, apply, Bus};
use polyturn_firmware::stepgen::Generator;
use polyturn_stm32_model::{Mcu, Params};
use polyturn_sync::steps::{StepPlan, StepTiming};

/// Timer clock and control tick of the board.
pub const TIMER_HZ: u32 = polyturn_sync::Timing::FIRMWARE.step_timer_hz;
pub const TICK_LEN: u32 = TIMER_HZ / polyturn_sync::Timing::FIRMWARE.tick_hz;
/// Where the DMA ring sits in the model's SRAM.
const RING: u32 = 0x2000_0400;

/// When the tick's interrupt runs: `latency` cycles (uniform in the range)
/// from TIM11's update to its read of the counters, then `cost` cycles of
/// the core's tick before the generator writes; each bus access `access`.
#[derive(Clone, Copy, Debug)]
pub struct Isr {
    pub latency: (u32, u32),
    pub cost: u32,
    pub access: u32,
    pub seed: u64,
}

impl Isr {
    pub const fn new(latency: (u32, u32)) -> Isr {
        Isr { latency, cost: 1_200, access: 2, seed: 1 }
    }
}

/// The model as the interrupt's bus: each access takes `access` cycles.
struct ModelBus<'a> {
    mcu: &'a mut Mcu,
    access: u64,
}

impl Bus for ModelBus<'_> {
    fn write(&mut self, addr: u32, value: u32) {
        let at = self.mcu.cycle() + self.access;
        self.mcu.run_until(at);
        self.mcu.write(addr, value);
    }
    fn read(&mut self, addr: u32) -> u32 {
        let at = self.mcu.cycle() + self.access;
        self.mcu.run_until(at);
        self.mcu.read(addr)
    }
    fn delay(&mut self, cycles: u32) {
        let at = self.mcu.cycle() + cycles as u64;
        self.mcu.run_until(at);
    }
}

/// The board: model, generator, tick schedule.
pub struct Rig {
    pub mcu: Mcu,
    pub gen: Generator,
    isr: Isr,
    rng: u64,
    /// cycle of TIM11's first update
    start: u64,
    pub ticks: u64,
    /// ticks whose interrupt ran into the next tick
    pub overruns: u64,
    /// generator failures (late ring, late arm)
    pub late: u64,
}

impl Rig {
    pub fn new(params: Params, isr: Isr) -> Rig {
        let mut mcu = Mcu::new(params);
        // TIM11 as `app::tick` sets it up: PSC 0, ARR = tick − 1, counting
        mcu.write(prog::TIM11 + prog::PSC, 0);
        mcu.write(prog::TIM11 + prog::ARR, TICK_LEN - 1);
        mcu.write(prog::TIM11 + prog::CR1, 1);
        let start = mcu.cycle() + TICK_LEN as u64;
        let mut bus = ModelBus { mcu: &mut mcu, access: isr.access as u64 };
        apply(&prog::COUNTER_INIT, &mut bus).expect("counter init");
        let mut gen = Generator::new(RING);
        gen.prepare(TICK_LEN, &mut bus);
        Rig { mcu, gen, isr, rng: isr.seed | 1, start, ticks: 0, overruns: 0, late: 0 }
    }

    fn latency(&mut self) -> u64 {
        // xorshift: repeatable jitter
        self.rng ^= self.rng << 13;
        self.rng ^= self.rng >> 7;
        self.rng ^= self.rng << 17;
        let (lo, hi) = self.isr.latency;
        lo as u64 + self.rng % (hi - lo + 1) as u64
    }

    /// The start of tick `k` (TIM11's update), in cycles.
    pub fn tick_start(&self, k: u64) -> u64 {
        self.start + k * TICK_LEN as u64
    }

    /// One control tick: `core` gets the pulse count and the cycle it was
    /// read at, returns the core's output; the generator then applies it.
    pub fn tick(&mut self, core: impl FnOnce(u16, u64) -> (StepPlan, bool, StepTiming)) {
        let k = self.ticks;
        let entry = (self.tick_start(k) + self.latency()).max(self.mcu.cycle());
        self.mcu.run_until(entry);
        // `app::tick` clears TIM11's update flag first thing
        self.mcu.write(prog::TIM11 + prog::SR, 0);
        let read_at = entry + 2 * self.isr.access as u64;
        self.mcu.run_until(read_at);
        let counted = self.mcu.read(prog::TIM2 + prog::CNT) as u16;
        let (plan, halt, timing) = core(counted, read_at);
        self.mcu.run_until(read_at + self.isr.cost as u64);
        let mut bus = ModelBus { mcu: &mut self.mcu, access: self.isr.access as u64 };
        if self.gen.tick(&plan, halt, &timing, &mut bus).is_err() {
            self.late += 1;
        }
        if self.mcu.cycle() >= self.tick_start(k + 1) {
            self.overruns += 1;
        }
        self.ticks += 1;
    }

    /// What the E-stop interrupt does at `cycle`: the halt program (its
    /// pulse released by a later tick, as the firmware's tick does).
    pub fn estop_at(&mut self, cycle: u64, timing: &StepTiming) {
        self.mcu.run_until(cycle);
        let mut bus = ModelBus { mcu: &mut self.mcu, access: self.isr.access as u64 };
        let _ = apply(&prog::HALT, &mut bus);
        self.gen.halted_elsewhere(timing);
    }
}
