//! The bench self-test end to end on the host: the
//! console's `selftest start`, the firmware's generator playing the plan
//! (`quadgen::bench`, its periods' edges at their exact TIM9 cycles), TIM3
//! counting them and latching the index, the real controller engaging and
//! stepping, the app's sampler feeding the generator's books to the judge
//! every millisecond. The jumper faults a bench can have each fail it with
//! the reason a machinist can act on.

use polyturn_firmware::quadgen::bench;
use polyturn_firmware::quadgen::bench::playback::{Event, Playback};
use polyturn_firmware::quadgen::TIMER_HZ;
use polyturn_sync::console::{handle, Action};
use polyturn_sync::selftest::{Failure, Verdict};
use polyturn_sync::steps::Dir;
use polyturn_sync::{Config, Controller, Fault, TickInput, Timing};

const TICK_HZ: u32 = Timing::FIRMWARE.tick_hz;
const CYCLES_PER_TICK: u64 = (TIMER_HZ / TICK_HZ) as u64;

/// The tick `ms` milliseconds into the run.
const fn tick_at_ms(ms: u64) -> u64 {
    ms * TICK_HZ as u64 / 1_000
}

/// What the jumpers and the board do wrong, if anything.
#[derive(Clone, Copy, Default)]
struct Bench {
    /// the count that TIM3 misses (an edge lost on a long jumper)
    lose_count: Option<usize>,
    /// PA2 and PA3 crossed
    swapped: bool,
    /// PA4 not wired to PB0
    no_index: bool,
    /// the index written after the period's second edge (an interrupt
    /// later than `quadgen::LATENCY_MAX`)
    late_index: bool,
    /// the tick at which one step pulse goes missing
    lose_step: Option<u64>,
    /// the tick at which the generator's interrupt dies
    generator_dies: Option<u64>,
    /// ... and stops without saying so (its books still say running)
    silently: bool,
}

/// TIM3: the count and the index latch, fed the generator's events as the
/// jumpers pass them on.
#[derive(Default)]
struct Tim3 {
    count: u16,
    latched: Option<u16>,
    seen: usize,
    index_due: bool,
}

impl Tim3 {
    fn see(&mut self, e: Event, bench: &Bench) {
        match e {
            Event::Count(d) => {
                self.seen += 1;
                let d = if bench.swapped { -d } else { d };
                if bench.lose_count != Some(self.seen) {
                    self.count = self.count.wrapping_add(d as i16 as u16);
                }
                if std::mem::take(&mut self.index_due) {
                    self.latched = Some(self.count);
                }
            }
            Event::Index if bench.late_index => self.index_due = true,
            Event::Index if !bench.no_index => self.latched = Some(self.count),
            Event::Index => {}
        }
    }
}

/// The step output: each plan's pulses counted two ticks later.
#[derive(Default)]
struct Output {
    emitted: u16,
    pipe: [(u16, Dir); 2],
}

/// Runs `selftest start` against `bench` to the end; the verdict.
fn run(config: Config, bench: Bench) -> (polyturn_sync::selftest::Report, Controller) {
    let mut c = Controller::new(config, Timing { tick_hz: TICK_HZ, step_timer_hz: TIMER_HZ });
    c.start(0, 0, 0);
    let (mut tim3, mut out) = (Tim3::default(), Output::default());
    let (reply, action) = handle(b"selftest start", &mut c);
    assert!(reply.starts_with("ok selftest started"), "{reply}");
    assert_eq!(action, Action::None);
    let (_, plan) = c.selftest_plan().expect("a plan to play");
    let (gen, _init) = bench::start(&plan).expect("the generator plays the plan");
    // the app's sampler starts it within a millisecond
    let start_tick = 7;
    let mut player = Playback::new(gen);
    let mut dead = false;
    for t in 0.. {
        dead |= bench.generator_dies == Some(t);
        if t >= start_tick && !dead {
            player.play((t + 1 - start_tick) * CYCLES_PER_TICK, |_, e| tim3.see(e, &bench));
        }
        let input =
            TickInput { lathe: tim3.count, index: tim3.latched.take(), emitted: out.emitted, ..TickInput::default() };
        let o = c.tick(&input);
        let (n, _) = out.pipe[(t % 2) as usize];
        out.emitted = out.emitted.wrapping_add(n);
        if bench.lose_step == Some(t) && n > 0 {
            out.emitted = out.emitted.wrapping_sub(1);
        }
        out.pipe[(t % 2) as usize] = (o.plan.count, o.plan.dir);
        if t % (TICK_HZ as u64 / 1000) == 0 {
            let mut books = bench::books(player.generator());
            books.running &= !dead || bench.silently;
            c.selftest_books(&books);
            c.service();
            if !c.selftest_running() {
                break;
            }
        }
        assert!(t < 20 * TICK_HZ as u64, "the self-test never ended");
    }
    (c.selftest_report().unwrap(), c)
}

#[test]
fn a_board_with_its_jumpers_right_passes_with_exact_counts_indexes_and_steps() {
    let (r, mut c) = run(Config::default(), Bench::default());
    assert_eq!(r.verdict, Verdict::Pass, "{r:?}");
    assert_eq!(r.rests, 3);
    assert_eq!(r.rpm, 300);
    // forward and back the same distance; 2400 counts a turn, so about
    // (1 s ramp + 2 s hold + 1 s ramp) × 5 turns/s = 15 turns
    assert_eq!(r.forward, -r.backward);
    assert!((35_000..37_000).contains(&r.forward), "{}", r.forward);
    // an index per turn crossed, both ways
    let turns = (r.forward / 2400) as u32;
    assert!((2 * turns..=2 * turns + 2).contains(&r.indexes), "{} for {turns} turns", r.indexes);
    // each hold: 2 s at 300 rpm × 2400 × 8/3 steps a count = 64 000 steps,
    // emitted as the gear's target moved (the lag is the same at both ends)
    for (steps, target) in r.holds {
        assert!((steps - target).abs() <= 2, "{steps} vs {target}");
        assert!((63_000..65_000).contains(&steps.abs()), "{steps}");
    }
    // at constant speed the cutter is on the target to a step; the ramps
    // lag more (the estimator follows the speed), well inside ferror (64)
    assert!(r.hold_lag_q16 <= 1 << 16, "hold lag {}", r.hold_lag_q16);
    assert!(r.ramp_lag_q16 < 16 << 16, "ramp lag {}", r.ramp_lag_q16);
    let (reply, _) = handle(b"selftest", &mut c);
    assert!(reply.starts_with("ok selftest pass rpm=300 forward="), "{reply}");
    // the cutter ramps down; the generator's index is no phase reference
    assert!(!c.status().indexed);
}

#[test]
fn a_lost_count_fails_at_the_next_rest_with_both_counts() {
    // (one count is within the index check's slack: the count check sees it)
    let (r, mut c) = run(Config::default(), Bench { lose_count: Some(5_000), ..Bench::default() });
    match r.verdict {
        Verdict::Fail(Failure::Counts { rest: 2, seen, made }) => assert_eq!(seen, made - 1),
        v => panic!("{v:?}"),
    }
    let (reply, _) = handle(b"selftest", &mut c);
    assert!(reply.starts_with("ok selftest fail: rest 2: counted "), "{reply}");
}

#[test]
fn crossed_a_and_b_fail_at_the_second_rest_saying_so() {
    let (r, mut c) = run(Config::default(), Bench { swapped: true, ..Bench::default() });
    match r.verdict {
        Verdict::Fail(Failure::Counts { rest: 2, seen, made }) => assert_eq!(seen, -made),
        v => panic!("{v:?}"),
    }
    let (reply, _) = handle(b"selftest", &mut c);
    assert!(reply.contains("PA2 and PA3 swapped"), "{reply}");
}

#[test]
fn a_missing_index_jumper_fails_on_the_index_count() {
    let (r, mut c) = run(Config::default(), Bench { no_index: true, ..Bench::default() });
    assert!(matches!(r.verdict, Verdict::Fail(Failure::Indexes { rest: 2, seen: 0, made }) if made >= 14), "{r:?}");
    let (reply, _) = handle(b"selftest", &mut c);
    assert!(reply.contains("jumper PA4 to PB0"), "{reply}");
}

#[test]
fn an_index_written_late_fails_on_the_count_it_latched() {
    // one count late: within the index check's slack, so no fault; the
    // judge compares the latch with the generator's count exactly
    let (r, mut c) = run(Config::default(), Bench { late_index: true, ..Bench::default() });
    match r.verdict {
        Verdict::Fail(Failure::IndexLate { rest: 2, seen, made }) => assert_eq!(seen, made + 1),
        v => panic!("{v:?}"),
    }
    let (reply, _) = handle(b"selftest", &mut c);
    assert!(reply.contains("the generator's interrupt was late"), "{reply}");
}

#[test]
fn a_step_lost_between_the_plan_and_the_pin_fails_the_test() {
    let (r, _) = run(Config::default(), Bench { lose_step: Some(tick_at_ms(4_000)), ..Bench::default() });
    assert_eq!(r.verdict, Verdict::Fail(Failure::Fault(Fault::StepOutput)), "{r:?}");
}

#[test]
fn a_generator_that_stops_is_a_failure_not_a_wait() {
    // (in the first ramp)
    let (r, _) = run(Config::default(), Bench { generator_dies: Some(tick_at_ms(2_400)), ..Bench::default() });
    assert_eq!(r.verdict, Verdict::Fail(Failure::Generator), "{r:?}");
}

#[test]
fn books_that_stop_moving_end_it_two_seconds_past_the_plan() {
    // (it dies in the second rest, 6.0 to 6.6 s, so nothing else goes
    // wrong meanwhile)
    let dies = Bench { generator_dies: Some(tick_at_ms(6_080)), silently: true, ..Bench::default() };
    let (r, c) = run(Config::default(), dies);
    assert_eq!(r.verdict, Verdict::Fail(Failure::Generator), "{r:?}");
    // 11.2 s of plan + 2 s, within two milliseconds (the books come once a
    // millisecond)
    let t = c.status().ticks;
    assert!((tick_at_ms(13_200)..tick_at_ms(13_202)).contains(&t), "{t}");
}

#[test]
fn opposite_sense_and_a_fractional_ratio_pass_too() {
    let c = Config::default().with("dir", "opposite").unwrap().with("ratio", "5/2").unwrap();
    let (r, _) = run(c, Bench::default());
    assert_eq!(r.verdict, Verdict::Pass, "{r:?}");
    // the cutter turns against the lathe: steps and counts opposite
    assert!(r.holds[0].0 < 0 && r.forward > 0, "{r:?}");
}
