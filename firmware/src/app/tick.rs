//! The control tick: TIM11's update interrupt at 25 kHz, below only the
//! E-stop (`board::PRIORITIES`). Reads the counters, runs the core's tick,
//! applies its output. The core is shared with lower priorities under its
//! own lock (`locked`: BASEPRI at the tick's level), not the global
//! critical section (`cs.rs`, one level lower, which the tick outranks).

use super::drivers::{self, Mmio, OutputPins, TIMER_HZ};
use super::safety;
use core::cell::RefCell;
use core::sync::atomic::{compiler_fence, AtomicU32, Ordering};
use cortex_m::interrupt::{CriticalSection, Mutex};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::pac;
use polyturn_firmware::stepgen::Generator;
use polyturn_firmware::xsteps::XSteps;
use polyturn_firmware::{board, esc};
use polyturn_sync::{Config, Controller, DriveKind, TickInput, Timing};

struct Io {
    core: Controller,
    steps: Generator,
    pins: OutputPins,
    x: XSteps,
    /// `safety::halts()` when the generator last heard of an E-stop halt
    halts_seen: u32,
}

/// cortex-m's Mutex: its token comes only from `locked` here, so a
/// `critical_section::with` token (`cs.rs`, which the tick outranks)
/// cannot open it.
static IO: Mutex<RefCell<Option<Io>>> = Mutex::new(RefCell::new(None));

/// BASEPRI masks every level numerically at or above it (PM0214 §2.1.3):
/// the tick's level and below, not the E-stop above it.
const TICK_MASK: u8 = board::TICK_LEVEL << 4;

/// The lock on `IO`: BASEPRI raised to the tick's level, so the tick (the
/// only other user of `IO`) waits, and the E-stop, which never touches
/// `IO`, does not. Only short copies inside. Raised through BASEPRI_MAX,
/// which never lowers it, so taking it where more is masked unmasks
/// nothing; restored on the way out.
fn locked<R>(f: impl FnOnce(&CriticalSection) -> R) -> R {
    let old = cortex_m::register::basepri::read();
    cortex_m::register::basepri_max::write(TICK_MASK);
    compiler_fence(Ordering::SeqCst);
    // SAFETY: nothing that touches `IO` can run until BASEPRI is restored
    let r = f(unsafe { &CriticalSection::new() });
    compiler_fence(Ordering::SeqCst);
    // SAFETY: restores the level this section found
    unsafe { cortex_m::register::basepri::write(old) };
    r
}
static TICKS: AtomicU32 = AtomicU32::new(0);
static LAST_SEEN: AtomicU32 = AtomicU32::new(0);
/// Tick cost in CPU cycles: running sum and worst, reset by `take_cost`.
static COST_SUM: AtomicU32 = AtomicU32::new(0);
static COST_WORST: AtomicU32 = AtomicU32::new(0);
/// Ticks whose segments the DMA reached before they were written.
static STEPS_LATE: AtomicU32 = AtomicU32::new(0);
/// `Generator::ndtr_lead` of the last arm, for the bench's log.
static NDTR_LEAD: AtomicU32 = AtomicU32::new(0);

pub const TIMING: Timing = polyturn_firmware::clocks::TIMING;

pub fn start(config: Config, mut pins: OutputPins) {
    pins.set_polarity(config.enable_active_high);
    pins.set_enable(false);
    let mut core = Controller::new(config, TIMING);
    let mut steps = Generator::new(drivers::ring_address());
    // STEP/DIR driven quietly from now on, the ring silent: before any tick
    steps.prepare(core.derived().steps.tick_len, &mut Mmio);
    drivers::set_halt_pulse(core.derived().steps.pulse);
    core.start(pac::TIM3.cnt().read().cnt(), drivers::steps_counted(), pac::TIM4.cnt().read().cnt());
    locked(|cs| {
        IO.borrow(cs).replace(Some(Io { core, steps, pins, x: XSteps::default(), halts_seen: safety::halts() }))
    });
    // SAFETY: DWT is only used here, for the tick's cycle count.
    let mut cp = unsafe { cortex_m::Peripherals::steal() };
    cp.DCB.enable_trace();
    cp.DWT.enable_cycle_counter();
    embassy_stm32::rcc::enable_and_reset::<embassy_stm32::peripherals::TIM11>();
    let t = pac::TIM11;
    t.psc().write_value(0);
    t.arr().write(|w| w.set_arr((TIMER_HZ / board::TICK_HZ - 1) as u16));
    t.dier().modify(|w| w.set_uie(true));
    t.cr1().modify(|w| w.set_cen(true));
    // SAFETY: the handler below is ready and the shared state is set.
    unsafe { interrupt::TIM1_TRG_COM_TIM11.enable() };
}

#[interrupt]
fn TIM1_TRG_COM_TIM11() {
    let start = cortex_m::peripheral::DWT::cycle_count();
    // first thing: stepgen's re-arm reads UIF to know the tick has not
    // ended under it (`program::arm`, its `Sync`)
    pac::TIM11.sr().write_value(pac::timer::regs::Sr1ch(0));
    // SAFETY: the token `IO` asks for, without raising BASEPRI: everything
    // else that opens `IO` runs at a lower priority (thread mode, or the
    // planning executor's interrupt) under `locked`, which masks this
    // handler, and the only interrupt above it (the E-stop) never opens it. (`.ci/qemu` checks no BASEPRI write is reachable from here.)
    run(unsafe { &CriticalSection::new() });
    TICKS.fetch_add(1, Ordering::Relaxed);
    let cost = cortex_m::peripheral::DWT::cycle_count().wrapping_sub(start);
    COST_SUM.fetch_add(cost, Ordering::Relaxed);
    COST_WORST.fetch_max(cost, Ordering::Relaxed);
}

/// The tick's work on the shared state: inputs in, the core's tick, its
/// output applied.
fn run(cs: &CriticalSection) {
    let halts_at_entry = safety::halts();
    // (try_: nothing else can hold it while the tick runs, and the tick
    // keeps no panic path)
    let Ok(mut io) = IO.borrow(cs).try_borrow_mut() else { return };
    let Some(io) = io.as_mut() else { return };
    // the encoder counters (lathe TIM3, cutter TIM4) read straight
    // into the core's seam; the E-stop and alarm as they are, or as the
    // E-stop interrupt saw them if it fired since
    let fired = safety::take_fired();
    let input = TickInput {
        lathe: pac::TIM3.cnt().read().cnt(),
        index: drivers::take_index(),
        emitted: drivers::steps_counted(),
        cutter: pac::TIM4.cnt().read().cnt(),
        estop_open: safety::estop_open() || fired.0,
        alarm: safety::alarm() || fired.1,
        x_emitted: io.x.emitted,
        lathe_edge: None,
    };
    let out = io.core.tick(&input);
    heard_of_halts(io);
    // the plan for two ticks on: RAM writes only (stepgen); a halt or
    // a (re-)arm applies its register program. Any other drive keeps
    // the step output halted.
    let stepping = io.core.config().drive == DriveKind::Stepper;
    let timing = io.core.derived().steps;
    if io.steps.tick(&out.plan, out.halt || !stepping, &timing, &mut Mmio).is_err() {
        STEPS_LATE.fetch_add(1, Ordering::Relaxed);
    }
    NDTR_LEAD.store(io.steps.ndtr_lead(), Ordering::Relaxed);
    // every tick, whatever the drive: a fault or halt stops the ESC too
    let bldc = io.core.config().drive == DriveKind::Bldc;
    let max = io.core.derived().limits.max_velocity;
    let forward = io.core.config().sense == polyturn_sync::Sense::Same;
    drivers::set_esc_pulse_us(esc::command(bldc, out.enable, out.halt, out.speed_q16, max, forward));
    io.pins.set_enable(out.enable);
    drivers::set_x_pins(io.x.tick(&out.x_plan, out.halt));
    // the E-stop pre-empts the tick: if it ran during this one, a write
    // above (an arm, the ESC's pulse) may have undone its stop. (The fence
    // keeps this load after those writes.)
    compiler_fence(Ordering::SeqCst);
    if safety::halts() != halts_at_entry {
        safety::stop_outputs();
        heard_of_halts(io);
    }
}

/// The E-stop interrupt halted the step output since the generator last
/// heard: it re-arms at the next tick without a halt.
fn heard_of_halts(io: &mut Io) {
    let now = safety::halts();
    if now != io.halts_seen {
        io.halts_seen = now;
        io.steps.halted_elsewhere();
    }
}

/// Runs `f` on the controller (console, planning, reports).
pub fn with_core<R>(f: impl FnOnce(&mut Controller) -> R) -> Option<R> {
    locked(|cs| IO.borrow(cs).borrow_mut().as_mut().map(|io| f(&mut io.core)))
}

/// Fits a cam table: the points are checked outside the lock (a pass over
/// the whole table), only the swap is under it.
pub fn fit_cam(h: &polyturn_sync::cam_upload::CamHeader, table: &'static [i32]) -> Option<Result<(), &'static str>> {
    let x = match polyturn_sync::controller::prepare_cam(h, table, TIMING) {
        Ok(x) => x,
        Err(e) => return Some(Err(e)),
    };
    with_core(|c| c.install_cam(h, x))
}

/// Applies the settings the drivers hold themselves (ENABLE polarity, the
/// pulse width a halt waits out) after a console change, at low priority.
pub fn apply_driver_settings() {
    locked(|cs| {
        if let Some(io) = IO.borrow(cs).borrow_mut().as_mut() {
            io.pins.set_polarity(io.core.config().enable_active_high);
            drivers::set_halt_pulse(io.core.derived().steps.pulse);
        }
    });
}

/// True if the tick ran since the last call (feeds the watchdog).
pub fn alive() -> bool {
    let now = TICKS.load(Ordering::Relaxed);
    now != LAST_SEEN.swap(now, Ordering::Relaxed)
}

/// Ticks whose step segments were written too late (each one halted the
/// output), since boot.
pub fn steps_late() -> u32 {
    STEPS_LATE.load(Ordering::Relaxed)
}

/// 1 if DMA2's NDTR counted the preloaded word at the last arm, else 0.
pub fn ndtr_lead() -> u32 {
    NDTR_LEAD.load(Ordering::Relaxed)
}

/// (ticks, average cycles, worst cycles) since the last call.
pub fn take_cost() -> (u32, u32, u32) {
    let ticks = TICKS.load(Ordering::Relaxed);
    let sum = COST_SUM.swap(0, Ordering::Relaxed);
    let worst = COST_WORST.swap(0, Ordering::Relaxed);
    (ticks, sum / board::TICK_HZ, worst)
}
