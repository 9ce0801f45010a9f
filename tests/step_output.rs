//! The cutter's step output on the model of TIM1, TIM2, TIM11 and DMA2
//! written from RM0383, with the real core and the firmware's
//! own register programs: what a driver receives, against what the core
//! believes and the exact target.

use polyturn_bench::hwsim::scenarios::{lathe, ramp, rocking, steady, Outcome, TIMING};
use polyturn_bench::hwsim::{driver::receive, Isr, TICK_LEN, TIMER_HZ};
use polyturn_firmware::stepgen::entries::Entry;
use polyturn_firmware::stepgen::program::{self as prog, apply, Bus, Op};
use polyturn_firmware::stepgen::RING_ENTRIES;
use polyturn_stm32_model::{Mcu, NdtrReading, Params, PwmModeSwitch};
use polyturn_sync::steps::Dir;
use polyturn_sync::Config;

fn config(ratio: &str, rpm: &str) -> Config {
    let c = Config::default().with("max-rate", "250000").unwrap().with("max-rpm", rpm).unwrap();
    c.with("ratio", ratio).unwrap()
}

/// The model on both readings of when DMA2's NDTR counts a word (see
/// `NdtrReading`): the generator learns which at each arm, and must give
/// the same edges on either.
fn both_ndtr_readings() -> [Params; 2] {
    [NdtrReading::AfterTransfer, NdtrReading::AtPreload].map(|ndtr| Params { ndtr, ..Params::default() })
}

/// Every pulse a driver needing the pulse width high and low sees, every
/// step where the core believes it is, and no more reversals than the
/// position the core commanded.
fn assert_clean(name: &str, o: &Outcome) {
    let r = &o.received;
    assert!(o.exact_agreement(), "{name}: driver {} core {} exact {}", r.steps, o.believed, o.exact);
    assert_eq!(r.unseen, 0, "{name}: pulses a driver could miss");
    assert!(
        r.pulses == 0 || (r.min_high >= o.pulse && r.min_low >= o.pulse),
        "{name}: high {} low {}",
        r.min_high,
        r.min_low
    );
    assert_eq!(r.dir_while_high, 0, "{name}: DIR changed during a pulse");
    assert!(r.reversals == 0 || r.min_dir_setup >= o.dir_setup, "{name}: DIR setup {}", r.min_dir_setup);
    assert!(r.reversals <= o.command_reversals.max(o.target_reversals), "{name}: {} reversals", r.reversals);
    assert_eq!((o.late, o.overruns), (0, 0), "{name}: late segments or overrun ticks");
}

#[test]
fn steps_land_within_two_cycles_of_the_ideal_train_from_10_hz_to_250_khz() {
    for (hz, p) in
        [10u64, 1_000, 7_777, 64_000, 123_457, 250_000].into_iter().flat_map(|h| both_ndtr_readings().map(|p| (h, p)))
    {
        let ticks = (TIMING.tick_hz as u64 * 2 / hz).clamp(400, TIMING.tick_hz.into());
        let o = steady(hz * 1000, ticks, Isr::new((200, 2_000)), p);
        assert!(o.received.steps > 0, "{hz} Hz, {:?}: the output started", p.ndtr);
        assert_clean(&format!("{hz} Hz, {:?}", p.ndtr), &o);
        assert!(o.faults.is_empty(), "{hz} Hz: {:?}", o.faults);
        if let Some(e) = o.spacing_error {
            assert!(e <= 2.0, "{hz} Hz: spacing error {e} cycles");
        }
    }
}

#[test]
fn the_interrupts_latency_moves_no_step() {
    // the same command with the tick's interrupt early, late and jittery:
    // the very same edges, to the cycle
    let [manual, preload] = both_ndtr_readings();
    let edges = |lat, p| steady(64_000_000, 600, Isr::new(lat), p).received.rises;
    let early = edges((200, 200), manual);
    assert!(early.len() > 1000);
    assert_eq!(early, edges((2_000, 2_000), manual));
    assert_eq!(early, edges((200, 2_000), manual));
    assert_eq!(early, edges((200, 2_000), preload), "NDTR counting the preload moves no step either");
}

#[test]
fn a_lathe_ramp_to_top_speed_loses_no_step_at_2_1_and_11_3() {
    for (ratio, rpm) in [("2", 2_300.0), ("11/3", 1_250.0)] {
        let c = config(ratio, &format!("{rpm}"));
        // 1 s to top speed: within the default max-accel
        for p in both_ndtr_readings() {
            let o = lathe(c, &ramp(2400.0, rpm, 1.0, 0.1), 2.3, Isr::new((200, 2_000)), p, None);
            assert!(o.received.pulses > 40_000, "{ratio}, {:?}: {} pulses", p.ndtr, o.received.pulses);
            assert_clean(ratio, &o);
            assert!(o.faults.is_empty(), "{ratio}, {:?}: {:?}", p.ndtr, o.faults);
        }
    }
}

#[test]
fn a_chuck_rocked_by_hand_never_doubles_a_step() {
    for p in both_ndtr_readings() {
        let o = lathe(config("2", "2000"), &rocking(40.0, 0.6), 0.8, Isr::new((200, 2_000)), p, None);
        assert!(o.target_reversals > 30);
        assert_clean("rocking", &o);
    }
}

#[test]
fn an_estop_mid_train_then_a_second_engagement_keeps_the_books_exact() {
    // under both readings of a switch into PWM mode (see the model)
    // and of when NDTR counts a word
    for (switch, p) in [PwmModeSwitch::Reevaluate, PwmModeSwitch::OnlyFromFrozen]
        .into_iter()
        .flat_map(|s| both_ndtr_readings().map(|p| (s, p)))
    {
        let params = Params { pwm_mode_switch: switch, ..p };
        // engaging again while the lathe turns: the catch-up needs time
        let o = lathe(
            config("2", "2000"),
            &ramp(2400.0, 600.0, 0.2, 0.5),
            2.5,
            Isr::new((200, 2_000)),
            params,
            Some((0.4, 0.45)),
        );
        assert_eq!(o.faults, vec!["estop"]);
        assert_clean("estop", &o);
    }
}

/// A bus straight onto the model, one cycle per access.
struct Direct<'a>(&'a mut Mcu);
impl Bus for Direct<'_> {
    fn write(&mut self, a: u32, v: u32) {
        self.0.step();
        self.0.write(a, v)
    }
    fn read(&mut self, a: u32) -> u32 {
        self.0.step();
        self.0.read(a)
    }
    fn delay(&mut self, c: u32) {
        let at = self.0.cycle() + c as u64;
        self.0.run_until(at)
    }
}

/// Arms TIM1 on a ring of pulse segments (or the program `patch` makes of
/// the arm program), halts it at `halt_at` and releases a high pulse when
/// the tick after `release_ticks` does (or at once, waiting, where
/// `wait`: the panic's halt); returns the model.
fn armed_run(patch: impl Fn(&mut Vec<Op>), halt_at: u64) -> Mcu {
    armed_run_halting(patch, halt_at, false)
}

fn armed_run_halting(patch: impl Fn(&mut Vec<Op>), halt_at: u64, wait: bool) -> Mcu {
    let mut mcu = Mcu::new(Params::default());
    mcu.write(prog::TIM11 + prog::PSC, 0);
    mcu.write(prog::TIM11 + prog::ARR, TICK_LEN - 1);
    mcu.write(prog::TIM11 + prog::CR1, 1);
    apply(&prog::COUNTER_INIT, &mut Direct(&mut mcu)).unwrap();
    let ring = 0x2000_0400;
    // every segment: 300 cycles low, then a 192-cycle pulse
    let pulse = Entry::pulses(300, 192, 1, Dir::Forward);
    for i in 0..RING_ENTRIES as u32 {
        for (j, w) in pulse.words().iter().enumerate() {
            mcu.write(ring + 4 * (prog::BURST_WORDS * i + j as u32), *w);
        }
    }
    let mut ops = prog::quiet(TICK_LEN, 0xFFFF).to_vec();
    ops.extend(prog::arm(ring, TICK_LEN));
    patch(&mut ops);
    // as the tick's interrupt does on entry
    mcu.write(prog::TIM11 + prog::SR, 0);
    apply(&ops, &mut Direct(&mut mcu)).unwrap();
    mcu.run_until(halt_at);
    if wait {
        apply(&prog::halt_and_wait(192), &mut Direct(&mut mcu)).unwrap();
    } else {
        apply(&prog::HALT, &mut Direct(&mut mcu)).unwrap();
        let tick = TICK_LEN as u64;
        let release = (halt_at / tick + prog::release_ticks(192, TICK_LEN) as u64) * tick;
        mcu.run_until(release);
        apply(&[prog::RELEASE], &mut Direct(&mut mcu)).unwrap();
    }
    mcu.run_until(halt_at + 10_000 + TICK_LEN as u64 * 4);
    mcu
}

#[test]
fn arming_counts_no_pulse_and_a_halt_cuts_none() {
    // halt at every phase of a pulse: TIM2 counts exactly the pulses the
    // driver saw, each a full pulse wide
    for wait in [false, true] {
        for offset in (0..492).step_by(7) {
            let mut mcu = armed_run_halting(|_| {}, 3 * TICK_LEN as u64 + offset, wait);
            let counted = mcu.read(prog::TIM2 + prog::CNT) as u64;
            let r = receive(mcu.edges(), 192, true);
            assert_eq!(counted, r.pulses, "halt at +{offset} (wait {wait})");
            assert!(r.pulses > 0 && r.min_high >= 192 && r.unseen == 0, "halt at +{offset} (wait {wait}): {r:?}");
            assert!(!mcu.pa8(), "STEP low in the end (wait {wait})");
        }
    }
}

#[test]
fn the_model_catches_an_arm_program_that_sets_trgo_after_its_ug() {
    // with MMS still at reset when UG is written, UG is TRGO (RM0383
    // §12.4.2) and TIM2 counts a pulse nobody sent
    let late_mms = |ops: &mut Vec<Op>| {
        let i = ops.iter().position(|op| *op == Op::Write(prog::TIM1 + prog::CR2, 0b100 << 4)).unwrap();
        let mms = ops.remove(i);
        let ug = ops.iter().position(|op| *op == Op::Write(prog::TIM1 + 0x14, 1)).unwrap();
        ops.insert(ug + 1, mms);
    };
    let mut bad = armed_run(late_mms, 2 * TICK_LEN as u64);
    let mut good = armed_run(|_| {}, 2 * TICK_LEN as u64);
    assert_eq!(good.read(prog::TIM2 + prog::CNT), 0);
    assert_eq!(bad.read(prog::TIM2 + prog::CNT), 1);
}

#[test]
fn a_slow_dma_still_loads_whole_segments() {
    // five transfers of 16 cycles: the burst takes 80 of a segment's
    // shortest 96; the tick writes the ring all the while
    let params = Params { dma_latency_cycles: 16, ..Params::default() };
    let o = steady(250_000_000, 600, Isr::new((200, 2_000)), params);
    assert_clean("250 kHz", &o);
    let o = lathe(config("2", "2000"), &rocking(40.0, 0.6), 0.8, Isr::new((200, 2_000)), params, None);
    assert_clean("rocking", &o);
}

#[test]
fn a_dir_setup_longer_than_a_tick_still_lets_the_cutter_reverse() {
    // 60 µs: a tick and a half. DIR turns first, the steps follow when
    // its setup has run out.
    let c = config("2", "2000").with("dir-setup", "60000").unwrap();
    let o = lathe(c, &rocking(40.0, 0.6), 0.9, Isr::new((200, 2_000)), Params::default(), None);
    assert!(o.received.reversals > 10, "{} reversals", o.received.reversals);
    assert_clean("long DIR setup", &o);
}

/// A tick that stops writing (a handler that hangs: the watchdog resets the
/// MCU within its longest period, 15.06 s at the slowest LSI, `iwdg`)
/// while TIM1 and the DMA run on at near the top rate with the least
/// latency: the ticks in flight go out, then silence to past the watchdog,
/// never an old segment's step again.
#[test]
fn a_tick_that_stops_writing_leaves_no_old_step_to_come_round() {
    use polyturn_bench::hwsim::Rig;
    use polyturn_sync::steps::pipe::StepPipe;
    let t = polyturn_sync::derived::Derived::new(&Config::default(), TIMING).steps;
    let mut rig = Rig::new(Params::default(), Isr::new((200, 200)));
    let mut books = StepPipe::default();
    books.start(0);
    // 249 000 steps/s: 12.45 steps a tick, Q16
    let q = |j: u64| ((j as i64) * 249_000 * 65_536) / TIMING.tick_hz as i64;
    const TICKS: u64 = 400;
    for k in 0..TICKS {
        rig.tick(|_, _| (books.plan(q(k), &t), false, t));
    }
    // the last plan runs in the tick after next (`steps::pipe`)
    let flight_end = rig.tick_start(TICKS + 2);
    let rises = |mcu: &Mcu| receive(mcu.edges(), 192, true).rises;
    rig.mcu.run_until(flight_end);
    let sent = rises(&rig.mcu).len();
    assert!(sent > 4_000, "{sent} steps before the hang");
    let watchdog_us =
        polyturn_firmware::iwdg::period_us(polyturn_firmware::iwdg::WATCHDOG_US, polyturn_firmware::iwdg::LSI_MIN_HZ);
    rig.mcu.run_until(flight_end + watchdog_us as u64 * (TIMER_HZ as u64 / 1_000_000));
    let late: Vec<u64> = rises(&rig.mcu).into_iter().skip(sent).collect();
    assert!(
        late.is_empty(),
        "{} old steps came round, the first {} cycles after the last tick",
        late.len(),
        late[0] - flight_end
    );
}
