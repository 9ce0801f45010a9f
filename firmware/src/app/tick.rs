//! The control tick: TIM11's update interrupt at 20 kHz, below only the
//! E-stop (`board::PRIORITIES`). Reads the counters, runs the core's
//! control, applies its output, and leaves the step plan to a handler one
//! level below (`plan`). The core is shared with lower priorities under its
//! own lock (`locked`: BASEPRI at the tick's level), not the global
//! critical section (`cs.rs`, below the plan, which both outrank).

mod plan;

use super::drivers::{self, OutputPins, TIMER_HZ};
use super::mmio::Mmio;
use super::{bldc, safety};
use core::cell::RefCell;
use core::sync::atomic::{compiler_fence, AtomicU32, Ordering};
use cortex_m::interrupt::{CriticalSection, Mutex};
use defmt::{info, warn};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::pac;
use polyturn_firmware::bldcout::Out;
use polyturn_firmware::board;
use polyturn_firmware::edgetime::{self, read::Gate, watch::Watch};
use polyturn_firmware::latency::Latency;
use polyturn_firmware::stepgen::Generator;
use polyturn_firmware::xsteps::XSteps;
use polyturn_sync::{Config, Controller, DriveKind, TickInput, Timing};

struct Io {
    core: Controller,
    steps: Generator,
    pins: OutputPins,
    x: XSteps,
    /// `halts()` when the generator last heard of a halt made elsewhere
    halts_seen: u32,
    /// whether the lathe's edge registers hold an edge (`edgetime::read`)
    gate: Gate,
    /// the edge clock's instants against the ticks run (`check_ticks`);
    /// none while the edge times are off, and through a save's stall
    watch: Option<Watch>,
    /// the BLDC drive's interface, as TIM10 is set up
    bldc: Out,
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
/// nothing; restored on the way out. Never inlined: each closure's copy is
/// a function of this module, in SRAM with the tick (`memory.x`), so a
/// section holding the tick off does not wait on the flash.
#[inline(never)]
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
/// When the tick ends, in cycles from its instant (`latency`).
pub static TICK_END: Latency = Latency::new();
pub use plan::PLAN_END;
/// TIM11's period in cycles: the tick's instant to the next.
pub const PERIOD: u32 = TIMER_HZ / board::TICK_HZ;
/// Ticks whose segments the DMA reached before they were written, or
/// whose step plan was not made by the next tick (`plan::late`).
static STEPS_LATE: AtomicU32 = AtomicU32::new(0);
/// `Generator::ndtr_lead`, learnt at boot, for the bench's log.
static NDTR_LEAD: AtomicU32 = AtomicU32::new(0);
/// Ticks whose interrupt never ran (`check_ticks`), since boot.
static TICKS_LOST: AtomicU32 = AtomicU32::new(0);
/// When the watch last looked (embassy's ms, read outside the lock: its
/// clock is right there): looks further apart than `WATCH_GAP_MS` are not
/// judged, the clock is measured again (`check_ticks`).
static LAST_LOOK_MS: AtomicU32 = AtomicU32::new(0);
/// Looks this far apart may alias the stamps (a look judges within 32 ms,
/// `edgetime::watch`): the service task looks every ms, so only a hold of
/// the whole MCU (a debugger's halt, a runaway section at the tick's
/// level) makes such a gap, and it can hide lost ticks.
const WATCH_GAP_MS: u32 = 20;

pub const TIMING: Timing = polyturn_firmware::clocks::TIMING;

/// The edge clock the start measured, for the log and the emulator's
/// replay: `first_instant`, then k0 mod 4 (the count in state (A, B) =
/// (0, 0), `edgetime::start::low_low`) at bit 16, and bit 18 set if the
/// start timed edges (a clock that could not be measured again since has
/// turned the core's off: `Controller::edge_timing`; a save tries again).
/// 0 until the start.
static EDGE_CLOCK: AtomicU32 = AtomicU32::new(0);
const EDGES_ON: u32 = 1 << 18;

// The stamps are embassy-time's ticks (TIM5, `edgetime`): one a µs, and a
// whole number of them per tick, as `edgetime` assumes.
const _: () = assert!(embassy_time::TICK_HZ == edgetime::STAMP_HZ as u64);
const _: () = assert!(TIMER_HZ.is_multiple_of(board::TICK_HZ) && TIMER_HZ / board::TICK_HZ <= 1 << 16);

pub fn start(config: Config, mut pins: OutputPins) {
    pins.set_polarity(config.enable_active_high);
    pins.set_enable(false);
    let core = Controller::new(config, TIMING);
    let mut steps = Generator::new(drivers::ring_address());
    // STEP/DIR driven quietly from now on, the ring silent: before any tick
    steps.prepare(core.derived().steps.tick_len, &mut Mmio);
    // (learnt once, here: the log says what the probe saw, armed or not)
    NDTR_LEAD.store(steps.ndtr_lead(), Ordering::Relaxed);
    drivers::set_halt_pulse(core.derived().steps.pulse);
    tick_timer();
    // the saved BLDC interface (its frame set up at boot), scaled to the
    // core's full speed, and its sense, before the first tick
    let drive = bldc::out_for(&core);
    bldc::set_sense(core.config());
    let io =
        Io { core, steps, pins, x: XSteps::default(), halts_seen: halts(), gate: Gate::Off, watch: None, bldc: drive };
    // Under the lock nothing but the E-stop runs: not the tick (its
    // interrupt is enabled in here, and waits for the lock's end), nor
    // anything that could come between TIM5's step and TIM11's start.
    let (low_low, s) = locked(|cs| {
        let low_low = edgetime::start::low_low(&mut Mmio);
        let mut io = io;
        // the lathe's count last: the first tick's count is counted from it
        io.core.start(pac::TIM3.cnt().read().cnt(), drivers::steps_counted(), pac::TIM4.cnt().read().cnt());
        IO.borrow(cs).replace(Some(io));
        let s = edgetime::start::start_tick(&mut Mmio);
        // an E-stop longer than a tick inside the start may have let an
        // update pend the interrupt before TIM11 was rewound: not a tick
        interrupt::TIM1_TRG_COM_TIM11.unpend();
        // SAFETY: the handlers below are ready and the shared state is set.
        unsafe {
            plan::enable();
            interrupt::TIM1_TRG_COM_TIM11.enable();
        }
        if let (Some(s), Some(k0), Some(io)) = (s, low_low, IO.borrow(cs).borrow_mut().as_mut()) {
            let clock = edgetime::start::clock(s, k0);
            io.core.start_edges(clock);
            io.gate = Gate::Waiting;
            EDGE_CLOCK.store(clock.first_instant as u32 | ((k0 & 3) as u32) << 16 | EDGES_ON, Ordering::Relaxed);
        }
        (low_low, s)
    });
    match (low_low, s) {
        (Some(k0), Some(s)) => {
            let first = s.wrapping_add(edgetime::STAMPS_PER_TICK);
            info!("edge times on: first tick at stamp {}, A and B low at count {}", first, k0)
        }
        (None, _) => warn!("edge times off: the lathe never held still between two reads of its count"),
        (_, None) => warn!("edge times off: TIM5 did not step, or the start was interrupted at every try"),
    }
}

/// TIM11 clocked and set up as the tick's timer, stopped: PSC 0, ARR one
/// tick less one (its update every tick), UIE; `edgetime::start` starts it.
fn tick_timer() {
    embassy_stm32::rcc::enable_and_reset::<embassy_stm32::peripherals::TIM11>();
    let t = pac::TIM11;
    t.psc().write_value(0);
    t.arr().write(|w| w.set_arr((TIMER_HZ / board::TICK_HZ - 1) as u16));
    t.dier().modify(|w| w.set_uie(true));
}

#[interrupt]
fn TIM1_TRG_COM_TIM11() {
    // first thing: stepgen's re-arm reads UIF to know the tick has not
    // ended under it (`program::arm`, its `Sync`)
    pac::TIM11.sr().write_value(pac::timer::regs::Sr1ch(0));
    // SAFETY: the token `IO` asks for, without raising BASEPRI: everything
    // else that opens `IO` runs at a lower priority (thread mode, or the
    // planning executor's interrupt) under `locked`, which masks this
    // handler, and the only interrupt above it (the E-stop) never opens it;
    // the plan, below it, opens it without a lock, and `run` does not if it
    // pre-empted one (`plan::making`). (`.ci/callgraph` checks no BASEPRI write is
    // reachable from here.)
    if run(unsafe { &CriticalSection::new() }) {
        TICKS.fetch_add(1, Ordering::Relaxed);
    }
    ended(&TICK_END);
}

/// A handler's end in `l`: TIM11's count (cycles since the tick's instant)
/// and whether its update flag says the next instant has passed.
#[inline(always)]
fn ended(l: &Latency) {
    let (count, sr) = (pac::TIM11.cnt().read().cnt() as u32, pac::TIM11.sr().read().uif());
    l.record(count, PERIOD, sr);
}

/// The tick's work on the shared state: inputs in, the core's control, its
/// output applied, the step plan handed on. False if the last tick's plan
/// still held the state: this tick did not run (`plan::late`).
fn run(cs: &CriticalSection) -> bool {
    let estops_at_entry = safety::halts();
    let bldc_stops = bldc::stops();
    // (both read before anything the E-stop's interrupt also writes)
    compiler_fence(Ordering::SeqCst);
    if plan::making() {
        plan::late();
        return false;
    }
    // (try_: nothing else can hold it while the tick runs, and the tick
    // keeps no panic path)
    let Ok(mut io) = IO.borrow(cs).try_borrow_mut() else { return true };
    let Some(io) = io.as_mut() else { return true };
    plan::settle(io);
    // the encoder counters (lathe TIM3, cutter TIM4) and the lathe's last
    // timed edge read straight into the core's seam; the E-stop and alarm
    // as they are, or as the E-stop interrupt saw them if it fired since
    let fired = safety::take_fired();
    // TIM3_SR first (the index, and whether an edge has been timed yet),
    // then the count and the last timed edge (`edgetime::read`)
    let flags = drivers::lathe_flags();
    io.gate.note(flags);
    let (lathe, lathe_edge) = edgetime::read::lathe(io.gate, &mut Mmio);
    let input = TickInput {
        lathe,
        index: drivers::index(flags),
        emitted: drivers::steps_counted(),
        cutter: pac::TIM4.cnt().read().cnt(),
        estop_open: safety::estop_open() || fired.0,
        alarm: safety::alarm() || fired.1,
        x_emitted: io.x.emitted,
        lathe_edge,
    };
    let out = io.core.control(&input);
    heard_of_halts(io);
    // the step output's own part of the tick here (a halt, or an arm, whose
    // register program holds only inside its tick: `program::arm`'s Sync),
    // and the plan for two ticks on, RAM writes only, one level below
    // (`plan`). Any other drive keeps the step output halted.
    let halt = out.halt || io.core.config().drive != DriveKind::Stepper;
    let timing = io.core.derived().steps;
    match io.steps.begin(halt, &timing, &mut Mmio) {
        Ok(true) => plan::hand_on(),
        // halted, or an arm that must wait: the plan made for the core's
        // books, unwritten (a failed arm is counted, as a late write)
        done => {
            let _ = io.core.plan_steps();
            if done.is_err() {
                STEPS_LATE.fetch_add(1, Ordering::Relaxed);
            }
        }
    }
    // every tick, whatever the drive: a halt stops the BLDC at once,
    // anything else not running it gets the stop from the next frame
    let run = io.core.config().drive == DriveKind::Bldc && out.enable;
    let forward = io.core.config().sense == polyturn_sync::Sense::Same;
    if out.halt {
        bldc::halt();
    } else {
        bldc::command(io.bldc.command(run, out.speed_q16, forward), bldc_stops);
    }
    io.pins.set_enable(out.enable);
    drivers::set_x_pins(io.x.tick(&out.x_plan, out.halt));
    // the E-stop pre-empts the tick: if it ran during this one, a write
    // above (an arm) may have undone its stop of the step output. (The
    // BLDC's command is ordered against it by its gate: writing its stop
    // again would only cut a stop pulse. The fence keeps this load after
    // those writes.)
    compiler_fence(Ordering::SeqCst);
    if safety::halts() != estops_at_entry {
        drivers::halt_steps();
        heard_of_halts(io);
    }
    true
}

/// Halts of the step output made outside the generator: the E-stop
/// interrupt's (`safety::halts`) and a late plan's (`plan::late`).
fn halts() -> u32 {
    safety::halts().wrapping_add(plan::lates())
}

/// The step output was halted elsewhere since the generator last heard
/// (`halts`): it re-arms at the next tick without a halt.
fn heard_of_halts(io: &mut Io) {
    let now = halts();
    if now != io.halts_seen {
        io.halts_seen = now;
        let timing = io.core.derived().steps;
        io.steps.halted_elsewhere(&timing);
    }
}

/// After lost ticks (a save's flash erase: `Controller::end_stall` drops the
/// core's edge clock; or a tick that never ran: `check_ticks`), the clock
/// measured again and given back to the core, under the lock, so that its
/// instants are the ticks it runs from here (`edgetime::start::next_instant`),
/// and the watch on the ticks started again from the next look. If it cannot be measured the
/// core's edge times go off, and the watch with them: a clock known to be
/// off must not place the lathe. Nothing if the start timed no edges.
pub fn restart_edges() {
    let on = EDGE_CLOCK.load(Ordering::Relaxed);
    if on & EDGES_ON == 0 {
        return;
    }
    let restarted = locked(|cs| {
        let first = edgetime::start::next_instant(&mut Mmio);
        let mut io = IO.borrow(cs).borrow_mut();
        let io = io.as_mut()?;
        let Some(first) = first else {
            io.core.stop_edges();
            io.watch = None;
            return Some(false);
        };
        let clock = edgetime::start::restarted(first, (on >> 16 & 3) as u16);
        EDGE_CLOCK.store(clock.first_instant as u32 | (on & !0xFFFF), Ordering::Relaxed);
        io.core.start_edges(clock);
        // (the service task's next look starts the watch again)
        io.watch = None;
        Some(true)
    });
    if restarted == Some(false) {
        warn!("edge times off: the tick's instant could not be measured again after lost ticks (a save's, or a tick that never ran)");
    }
}

/// A save is about to stall the CPU (its erase): the core is told
/// (`Controller::begin_stall`), and the watch on the ticks stops until
/// `restart_edges` measures the clock again.
pub fn begin_stall() {
    locked(|cs| {
        if let Some(io) = IO.borrow(cs).borrow_mut().as_mut() {
            io.core.begin_stall();
            io.watch = None;
        }
    });
}

/// Every ms from the service task: ticks whose interrupt never ran
/// (`edgetime::watch`), from the next tick's instant as `next_instant`
/// measures it and the ticks run, under the lock. Any lost puts the edge
/// times' instants a tick early for good: the clock is measured again
/// (`restart_edges`), as after a save.
pub fn check_ticks() {
    let now_ms = embassy_time::Instant::now().as_millis() as u32;
    let gap = now_ms.wrapping_sub(LAST_LOOK_MS.swap(now_ms, Ordering::Relaxed));
    let lost = locked(|cs| {
        let mut io = IO.borrow(cs).borrow_mut();
        let io = io.as_mut().filter(|io| io.core.edge_timing())?;
        // (a measurement no try could make: looked at again next ms)
        let next = edgetime::start::next_instant(&mut Mmio)?;
        let ticks = TICKS.load(Ordering::Relaxed);
        let Some(watch) = io.watch.as_mut() else {
            // the first look since the clock was measured: judged from here
            io.watch = Some(Watch::new(next, ticks));
            return None;
        };
        // a look too far from the last cannot tell: `None`, as the watch
        // says itself of looks 32 ms apart
        Some(watch.look(next, ticks).filter(|_| gap <= WATCH_GAP_MS))
    });
    match lost {
        Some(Some(0)) | None => {}
        Some(Some(n)) => {
            let total = TICKS_LOST.fetch_add(n, Ordering::Relaxed).wrapping_add(n);
            warn!("{} tick(s) never ran ({} since boot): the edge times' clock is measured again", n, total);
            restart_edges();
        }
        Some(None) => {
            warn!("the watch on lost ticks did not look for {} ms: the edge times' clock is measured again", gap);
            restart_edges();
        }
    }
}

/// The lathe's last timed edge, read as the tick reads it, with k0 mod 4
/// (A and B low: `EDGE_CLOCK`), for the bench's log; `None` until the tick
/// has seen a capture (the read clears CC1IF, which nothing looks at from
/// then on).
pub fn last_edge() -> Option<(polyturn_sync::edges::EdgeRegs, u16)> {
    let gate = locked(|cs| IO.borrow(cs).borrow().as_ref().map(|io| io.gate));
    if gate != Some(Gate::Open) {
        return None;
    }
    let k0 = (EDGE_CLOCK.load(Ordering::Relaxed) >> 16 & 3) as u16;
    edgetime::read::lathe(Gate::Open, &mut Mmio).1.map(|e| (e, k0))
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
/// pulse width a halt waits out, the BLDC drive's interface and sense)
/// after a console change, at low priority. The BLDC's scale (a 64-bit
/// division) is worked out between two short copies under the lock: only
/// thread mode changes the settings, and nothing else runs there meanwhile.
pub fn apply_driver_settings() {
    let read = |io: &Io| (*io.core.config(), io.core.derived().limits.max_velocity, io.core.derived().steps.pulse);
    let Some((config, max_q16, pulse)) = locked(|cs| IO.borrow(cs).borrow().as_ref().map(read)) else { return };
    let out = Out::new(&config, max_q16);
    drivers::set_halt_pulse(pulse);
    locked(|cs| {
        if let Some(io) = IO.borrow(cs).borrow_mut().as_mut() {
            io.pins.set_polarity(config.enable_active_high);
            // (a new scale alone keeps the frame: no reprogram, whose
            // restart would cut a frame short)
            if !out.same_frame(&io.bldc) {
                bldc::set_up(&out);
            }
            io.bldc = out;
            bldc::set_sense(&config);
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

/// 1 if DMA2's NDTR counted the preloaded word at the boot's probe, else 0.
pub fn ndtr_lead() -> u32 {
    NDTR_LEAD.load(Ordering::Relaxed)
}

/// Ticks run since boot.
pub fn ticks() -> u32 {
    TICKS.load(Ordering::Relaxed)
}
