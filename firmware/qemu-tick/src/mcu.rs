use crate::meter::{calibration_loop, measure, Costs, TIMING};
use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use polyturn_sync::edges::{EdgeClock, EdgeRegs};
use polyturn_sync::gear::Scale;
use polyturn_sync::steps::{Dir, StepPlan};
use polyturn_sync::{Config, Controller, State, TickInput, TickOutput};

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("panic: {}", info);
    debug::exit(debug::EXIT_FAILURE);
    loop {}
}

/// A's last rise while the lathe went from `before` to `after` (24.8
/// counts) in tick `k` (instant 40 + 40k µs): A rises as the count becomes
/// 1 (mod 4), the count after it latched, at the µs it crossed.
fn rise_between(before: u32, after: u32, k: u32) -> Option<EdgeRegs> {
    let top = after >> 8;
    let count = top - (top + 3) % 4;
    if count << 8 <= before || after == before {
        return None;
    }
    let into = ((count << 8) - before) * 40 / (after - before);
    Some(EdgeRegs { count: count as u16, stamp: (40 * k + into) as u16 })
}

/// The tick under test, kept out of line so its cost is measured alone:
/// the control part, as the firmware's tick runs it.
#[inline(never)]
#[no_mangle]
pub fn polyturn_tick(ctl: &mut Controller, input: &TickInput) -> TickOutput {
    ctl.control(input)
}

/// The step plan the tick leaves, as the firmware's plan handler runs it
/// one level below the tick (`app/tick/plan.rs`), measured on its own.
#[inline(never)]
#[no_mangle]
pub fn polyturn_plan(ctl: &mut Controller) -> StepPlan {
    ctl.plan_steps()
}

/// Cost of the tick's building blocks alone (instructions, common path).
fn parts(syst: &SYST, per_1201: u32) {
    use polyturn_sync::encoder::Extender;
    use polyturn_sync::estimator::Estimator;
    use polyturn_sync::follower::{Follower, Limits};
    use polyturn_sync::gear::Gear;
    use polyturn_sync::steps::{plan, Prev, StepTiming};
    let instr = |counts: u32| counts as u64 * 1201 / per_1201 as u64;
    let n = 1000u32;
    let mut gear = Gear::new(Scale::new(2, 1, 3200, 2400).unwrap());
    let mut est = Estimator::new(2500);
    let mut ext = Extender::new(0);
    let lim = Limits { max_velocity: 8 << 16, max_accel: 42, start_velocity: 0 };
    let mut f = Follower { position: 0, velocity: 174_763 };
    let t = StepTiming { tick_len: 3840, min_period: 384, dir_setup: 480, pulse: 192 };
    let (mut g, mut e, mut x, mut fo, mut p, mut ed) = (0, 0, 0, 0, 0, 0);
    let mut target = 0i64;
    let mut timer =
        polyturn_sync::edges::EdgeTimer::new(EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false });
    let mut lathe = Extender::new(0);
    let mut rise = None;
    for k in 0..n {
        // a count a tick, A rising every fourth (as at 600 rpm)
        lathe.update(k as u16);
        rise = rise_between(k.saturating_sub(1) << 8, k << 8, k).or(rise);
        ed += measure(syst, || {
            core::hint::black_box(timer.measure(core::hint::black_box(rise), &lathe));
        });
        g += measure(syst, || gear.advance(core::hint::black_box(1)));
        e += measure(syst, || est.update(core::hint::black_box((k % 25 != 0) as i32)));
        x += measure(syst, || {
            core::hint::black_box(ext.update(core::hint::black_box(k as u16)));
        });
        target += 174_763;
        let from = f.position;
        fo += measure(syst, || f.track(core::hint::black_box(target), 174_763, &lim));
        let to = f.position;
        p += measure(syst, || {
            core::hint::black_box(plan(from, to, (from + (1 << 15)) >> 16, &Prev::idle(Dir::Forward), &t));
        });
    }
    hprintln!(
        "parts (instructions each, incl. ~6 of measurement): gear {} estimator {} counter {} follower {} step plan {} edge timer {}",
        instr(g) / n as u64,
        instr(e) / n as u64,
        instr(x) / n as u64,
        instr(fo) / n as u64,
        instr(p) / n as u64,
        instr(ed) / n as u64
    );
}

#[entry]
fn main() -> ! {
    let mut cp = cortex_m::Peripherals::take().unwrap();
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
    let syst = &cp.SYST;

    let per_1201 = measure(syst, calibration_loop).max(1);

    let config = Config::default().with("max-rpm", "1000").unwrap();
    let mut ctl = Controller::new(config, TIMING);
    ctl.start(0, 0, 0);
    // the board times A's rises (`edges`): the first tick's instant at
    // stamp 40, the count 0 with A and B low
    ctl.start_edges(EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false });
    let mut rise: Option<EdgeRegs> = None;
    // A synthetic lathe: up to 600 rpm (0.96 counts per tick, 24.8 fixed
    // point) in 0.2 s, hold, down in 0.2 s, then at rest.
    let (mut pos_q8, mut emitted) = (0u32, 0u32);
    // plans in flight: the hardware runs each two ticks after it was made
    let mut flight = [0u32; 2];
    let (mut tick, mut plan) = (Costs::default(), Costs::default());
    let total = 30_000u32;
    let ramp = |k: u32| -> u32 {
        let top = 246u32;
        match k {
            0..5_000 => top * k / 5_000,
            5_000..20_000 => top,
            20_000..25_000 => top * (25_000 - k) / 5_000,
            _ => 0,
        }
    };
    let mut engaged = false;
    for k in 0..total {
        let speed_q8 = ramp(k);
        let before = pos_q8;
        pos_q8 += speed_q8;
        rise = rise_between(before, pos_q8, k).or(rise);
        let input = TickInput {
            lathe: (pos_q8 >> 8) as u16,
            emitted: emitted as u16,
            lathe_edge: rise,
            ..TickInput::default()
        };
        let mut out = TickOutput::default();
        let cost = measure(syst, || out = polyturn_tick(&mut ctl, &input));
        let plan_cost = measure(syst, || out.plan = polyturn_plan(&mut ctl));
        // A perfect step generator: every planned step is emitted, two
        // ticks later; the counter counts up whichever way DIR points.
        emitted = emitted.wrapping_add(flight[0]);
        flight = [flight[1], out.plan.count as u32];
        if !engaged {
            engaged = ctl.engage().is_ok();
        }
        if ctl.state() == State::Synced && speed_q8 == 246 {
            tick.add(cost);
            plan.add(plan_cost);
        }
    }
    let lathe = (pos_q8 >> 8) as i64;
    let d = ctl.derived();
    let exact = Scale::round(d.scale, lathe) + ctl.turn_offset_steps();
    let cutter = ctl.status().cutter_steps;
    let (avg, worst) = tick.instructions(per_1201);
    let (plan_avg, plan_worst) = plan.instructions(per_1201);
    hprintln!("calibration: {} systick counts per 1201 instructions", per_1201);
    hprintln!("ticks: {} total, {} synced at 600 rpm", total, tick.n);
    hprintln!("tick instructions: average {} (synced, common path), worst {}", avg, worst);
    hprintln!("step plan instructions (one level below the tick): average {}, worst {}", plan_avg, plan_worst);
    hprintln!("gear: lathe {} counts, exact target {} steps, cutter {} steps", lathe, exact, cutter);
    parts(syst, per_1201);
    let locked = crate::locked::report(syst, per_1201);
    let ok = tick.n > 10_000 && exact == cutter && locked.is_some();
    hprintln!("{}", if ok { "1 passed, 0 failed" } else { "0 passed, 1 failed" });
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    loop {}
}
