//! The control tick: TIM11's update interrupt at 20 kHz, below only the
//! E-stop (`board::PRIORITIES`). Reads the counters, runs the core's
//! control and its step plan, applies its output, and leaves the plan's
//! writing into the ring to a handler one level below (`plan`). The core is shared with lower priorities under its
//! own lock (`locked`: BASEPRI at the tick's level), not the global
//! critical section (`cs.rs`, below the plan, which both outrank).
//!
//! Here the interrupt and its start; the shared state and its lock in
//! `shared`, the edge clock's watch in `watch`, the counts for the log in
//! `telemetry`, the step plan's writing in `plan`.

mod plan;
mod shared;
mod telemetry;
mod watch;

pub use shared::{apply_driver_settings, fit_cam, with_core};
use shared::{locked, Io, IO};
pub use telemetry::{alive, ndtr_lead, steps_late, ticks};
use telemetry::{NDTR_LEAD, STEPS_LATE, TICKS};
pub use watch::{begin_stall, check_ticks, last_edge, restart_edges};
use watch::{EDGES_ON, EDGE_CLOCK};

use super::drivers::{self, OutputPins, TIMER_HZ};
use super::mmio::Mmio;
use super::{bldc, safety};
use core::sync::atomic::{compiler_fence, Ordering};
use cortex_m::interrupt::CriticalSection;
use defmt::{info, warn};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::pac;
use polyturn_firmware::board;
use polyturn_firmware::edgetime::{self, read::Gate};
use polyturn_firmware::latency::Latency;
use polyturn_firmware::stepgen::Generator;
use polyturn_firmware::xsteps::XSteps;
use polyturn_sync::steps::{StepPlan, StepTiming};
use polyturn_sync::{Config, Controller, DriveKind, TickInput, Timing};

/// When the tick ends, in cycles from its instant (`latency`).
pub static TICK_END: Latency = Latency::new();
pub use plan::{past_next as plans_past_next, PLAN_END};
/// TIM11's period in cycles: the tick's instant to the next.
pub const PERIOD: u32 = TIMER_HZ / board::TICK_HZ;

pub const TIMING: Timing = polyturn_firmware::clocks::TIMING;

// The stamps are embassy-time's ticks (TIM5, `edgetime`): one a µs, and a
// whole number of them per tick, as `edgetime` assumes.
const _: () = assert!(embassy_time::TICK_HZ == edgetime::STAMP_HZ as u64);
const _: () = assert!(TIMER_HZ.is_multiple_of(board::TICK_HZ) && TIMER_HZ / board::TICK_HZ <= 1 << 16);

pub fn start(config: Config, mut pins: OutputPins) {
    pins.set_polarity(config.enable_active_high);
    pins.set_enable(false);
    let core = Controller::new(config, TIMING);
    let mut steps = Generator::new(drivers::ring_address());
    let timing = core.derived().steps;
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
    let io = Io { core, pins, x: XSteps::default(), gate: Gate::Off, watch: None, bldc: drive };
    // Under the lock nothing but the E-stop runs: not the tick (its
    // interrupt is enabled in here, and waits for the lock's end), nor
    // anything that could come between TIM5's step and TIM11's start.
    let (low_low, s) = locked(|cs| {
        let low_low = edgetime::start::low_low(&mut Mmio);
        let mut io = io;
        // the lathe's count last: the first tick's count is counted from it
        io.core.start(pac::TIM3.cnt().read().cnt(), drivers::steps_counted(), pac::TIM4.cnt().read().cnt());
        IO.borrow(cs).replace(Some(io));
        plan::install(steps, timing, cs);
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
    // else that opens `IO` runs at a lower priority (thread mode) under
    // `locked`, which masks this handler, and the only interrupt above it
    // (the E-stop) never opens it; the plan's handler, below it, opens only
    // the generator, which `plan::writer` hands the tick when it is free.
    // (`.ci/callgraph` checks no BASEPRI write is reachable from here.)
    run(unsafe { &CriticalSection::new() });
    TICKS.fetch_add(1, Ordering::Relaxed);
    ended(&TICK_END);
}

/// A handler's end in `l`: TIM11's count (cycles since the tick's instant)
/// and whether its update flag says the next instant has passed.
#[inline(always)]
fn ended(l: &Latency) {
    ended_after(l, false);
}

/// `ended`, where `passed` says the next instant has passed anyway (a tick
/// has run since, and cleared the flag).
#[inline(always)]
fn ended_after(l: &Latency, passed: bool) {
    let (count, sr) = (pac::TIM11.cnt().read().cnt() as u32, pac::TIM11.sr().read().uif());
    l.record(count, PERIOD, sr || passed);
}

/// The tick's work on the shared state: inputs in, the core's control and
/// step plan, its output applied, the plan handed on to be written.
fn run(cs: &CriticalSection) {
    let estops_at_entry = safety::halts();
    let bldc_stops = bldc::stops();
    // (both read before anything the E-stop's interrupt also writes)
    compiler_fence(Ordering::SeqCst);
    plan::at_entry();
    // (try_: nothing else can hold it while the tick runs, and the tick
    // keeps no panic path)
    let Ok(mut io) = IO.borrow(cs).try_borrow_mut() else { return };
    let Some(io) = io.as_mut() else { return };
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
    // the plan for two ticks on, every tick (the core's books count it
    // whether it is written or not)
    let plan = io.core.plan_steps();
    // Any drive but a stepper keeps the step output halted.
    let halt = out.halt || io.core.config().drive != DriveKind::Stepper;
    let timing = io.core.derived().steps;
    let mut writer = plan::writer(cs);
    step_output(writer.as_mut().and_then(|w| w.as_mut()), plan, halt, &timing);
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
        if let Some(w) = writer.as_mut().and_then(|w| w.as_mut()) {
            heard_of_halts(w, &timing);
        }
    }
}

/// The step output's own part of the tick, the generator in hand (`w`):
/// a halt, or an arm, whose register program holds only inside its tick
/// (`program::arm`'s Sync), and the plan handed on to be written one level
/// below. None while the plan's handler writes: no arm this tick, a halt
/// on the registers.
fn step_output(w: Option<&mut plan::Writer>, plan: StepPlan, halt: bool, timing: &StepTiming) {
    let Some(w) = w else {
        if halt {
            plan::halt_busy();
        } else {
            plan::hand_on(&plan);
        }
        return;
    };
    plan::settle(w);
    w.timing = *timing;
    heard_of_halts(w, timing);
    match w.steps.begin(halt, timing, &mut Mmio) {
        Ok(true) => plan::hand_on(&plan),
        // halted, or an arm that must wait: the plan unwritten (the books
        // catch any step in it; a failed arm is counted, as a late write)
        Ok(false) => {}
        Err(_) => {
            STEPS_LATE.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// Halts of the step output made outside the generator: the E-stop
/// interrupt's (`safety::halts`), and the tick's while the plan's handler
/// held the generator or for a late plan (`plan::halts_here`).
fn halts() -> u32 {
    safety::halts().wrapping_add(plan::halts_here())
}

/// The step output was halted elsewhere since the generator last heard
/// (`halts`): it re-arms at a later tick without a halt.
fn heard_of_halts(w: &mut plan::Writer, timing: &StepTiming) {
    let now = halts();
    if now != w.halts_seen {
        w.halts_seen = now;
        w.steps.halted_elsewhere(timing);
    }
}
