//! The segments against the plans they come from, and the bus programs'
//! own semantics. The timer itself is checked in `tests/stepgen_model.rs`,
//! against the model written from RM0383.

use super::entries::{Entry, Layout, SILENT};
use super::program::{apply, Bus, Op};
use super::*;
use polyturn_sync::steps::{plan, Prev};
use proptest::prelude::*;
use std::vec::Vec;

const T: StepTiming = StepTiming { tick_len: 3840, min_period: 192, dir_setup: 480, pulse: 96 };

/// Rising edges (absolute cycles) a list of segments makes from `start`.
fn rises(segments: &[Entry], start: i64) -> (Vec<i64>, i64) {
    let (mut at, mut out) = (start, Vec::new());
    for s in segments {
        for _ in 0..=s.rcr {
            if s.ccr1 <= s.arr {
                out.push(at + s.ccr1 as i64);
            }
            at += s.arr as i64 + 1;
        }
    }
    (out, at)
}

proptest! {
    /// Whatever the command does, the segments put every rising edge where
    /// the plan says, join up with no gap, and each is long enough for the
    /// DMA and short enough for the 16-bit timer.
    #[test]
    fn segments_put_every_step_where_the_plan_says(
        moves in proptest::collection::vec(-400_000i64..400_000, 1..120),
        board in prop::sample::select(vec![None, Some(96u32), Some(240), Some(LONGEST_PULSE)]),
    ) {
        // this file's timing, or the board's tick with a pulse from the
        // shortest (1 µs) to the console's longest, at its shortest period
        let t = match board {
            Some(pulse) => StepTiming { tick_len: 4800, min_period: 2 * pulse, dir_setup: 480, pulse },
            None => T,
        };
        let (mut pos, mut emitted, mut prev, mut layout) = (0i64, 0i64, Prev::idle(Dir::Forward), Layout::armed(Dir::Forward));
        let mut timeline = 0i64; // where the segments end, absolute
        for (k, dv) in moves.iter().enumerate() {
            let p = plan(pos, pos + dv, emitted, &prev, &t);
            prev = prev.after(&p, &t);
            let tick0 = k as i64 * t.tick_len as i64;
            let segs = layout.segments(&p, &t, MIN_SEGMENT);
            let (got, end) = rises(&segs, timeline);
            let want: Vec<i64> = (0..p.count as u32).map(|i| tick0 + p.at(i) as i64).collect();
            prop_assert_eq!(got, want);
            for s in &segs {
                prop_assert!(s.cycles() >= MIN_SEGMENT, "segment of {} cycles", s.cycles());
                prop_assert!(s.arr < SILENT && s.rcr <= 255);
                // DIR changes at the tick's first segment, before any pulse
                if p.count > 0 {
                    prop_assert_eq!(s_dir(s), p.dir);
                }
            }
            // the last segment starts late in the tick: the DMA asks for the
            // next tick's first segment then, and not before
            let last_len = segs.last().unwrap().cycles() as i64;
            // (or where a pulse that ends within a pulse of the tick's end
            // rises, if that is earlier: long pulses)
            let boundary = (entries::late_boundary(t.tick_len) - MIN_SEGMENT).min(t.tick_len - 2 * t.pulse);
            let late = tick0 + boundary as i64;
            prop_assert!(end - last_len >= late, "the last segment starts {} cycles into the tick", end - last_len - tick0);
            prop_assert!(segs.len() <= entries::MAX_SEGMENTS);
            timeline = end;
            emitted += if p.dir == Dir::Forward { p.count as i64 } else { -(p.count as i64) };
            pos += dv;
        }
    }
}

/// The console's longest STEP pulse in the board's timer cycles (96 MHz).
const LONGEST_PULSE: u32 = (polyturn_sync::config::table::PULSE.hi as u64 * 96 / 1000) as u32;

/// Each tick's last segment starts late (`late_boundary`), or where a
/// pulse ending within a pulse of the tick's end rises: past half the tick
/// for the console's longest pulse.
const _: () = assert!(4800 - 2 * LONGEST_PULSE >= 4800 / 2, "the console's longest pulse leaves the last segment late");

fn s_dir(s: &Entry) -> Dir {
    if s.ccr2 == 0 {
        Dir::Reverse
    } else {
        Dir::Forward
    }
}

/// The reads of a tick that writes its plan, NDTR reading `ndtr`
/// throughout: NDTR before writing, the stream on, NDTR after the first
/// entry and at the end (`write_plan`), NDTR for the silencing
/// (`silence_behind`).
fn write_tick(ndtr: u32) -> Vec<u32> {
    vec![ndtr, 1, ndtr, ndtr, ndtr]
}

/// The reads of a tick that arms (quietened already) and writes its first
/// window: TIM11 at `tim11` and its UIF 0, NDTR `ndtr` with TIM1's update
/// flag `uif` (the lead's reading), then `write_tick`'s.
fn arm_tick(tim11: u32, ndtr: u32, uif: u32) -> Vec<u32> {
    [vec![tim11, 0, ndtr, uif], write_tick(ndtr)].concat()
}

/// A bus that answers reads from a script and logs writes.
#[derive(Default)]
struct Script {
    reads: Vec<u32>,
    writes: Vec<(u32, u32)>,
}

impl Bus for Script {
    fn write(&mut self, addr: u32, value: u32) {
        self.writes.push((addr, value));
    }
    fn delay(&mut self, cycles: u32) {
        self.writes.push((u32::MAX, cycles));
    }
    fn read(&mut self, _addr: u32) -> u32 {
        if self.reads.is_empty() {
            0
        } else {
            self.reads.remove(0)
        }
    }
}

#[test]
fn a_wait_gives_up_after_its_polls_and_stops_the_program() {
    let ops = [Op::WaitClear { addr: 4, mask: 1, polls: 3 }, Op::Write(8, 1)];
    let mut bus = Script { reads: vec![1, 1, 1, 0], ..Default::default() };
    assert_eq!(apply(&ops, &mut bus), Err(0));
    assert!(bus.writes.is_empty());
    let mut bus = Script { reads: vec![1, 1, 0], ..Default::default() };
    assert_eq!(apply(&ops, &mut bus), Ok(()));
    assert_eq!(bus.writes, vec![(8, 1)]);
}

#[test]
fn sync_copies_the_tick_count_plus_its_delay_unless_too_late() {
    let op = [Op::Sync { from: 1, to: 2, add: 8, limit: 3839, flag: 3, mask: 1 }];
    let mut bus = Script { reads: vec![100, 0], ..Default::default() };
    assert_eq!(apply(&op, &mut bus), Ok(()));
    assert_eq!(bus.writes, vec![(2, 108)]);
    let mut bus = Script { reads: vec![3831, 0], ..Default::default() };
    assert_eq!(apply(&op, &mut bus), Err(0));
    assert!(bus.writes.is_empty());
    // the update flag set after the copy: the count may be the next
    // tick's, so the program fails (and the generator halts what it set)
    let mut bus = Script { reads: vec![5, 1], ..Default::default() };
    assert_eq!(apply(&op, &mut bus), Err(0));
    assert_eq!(bus.writes, vec![(2, 13)]);
}

#[test]
fn a_halted_generator_writes_nothing_until_it_re_arms() {
    let mut g = Generator::new(0x2000_0000);
    let mut bus = Script::default();
    g.prepare(T.tick_len, &mut bus);
    bus.writes.clear();
    g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
    assert!(bus.writes.is_empty(), "not armed: nothing to halt");
    // arm (quietened at boot): TIM11 at 0, no update; NDTR full and TIM1
    // without an update (the reading of NDTR); NDTR full, stream on, NDTR full
    bus.reads = arm_tick(0, program::RING_WORDS, 0);
    g.tick(&StepPlan::default(), false, &T, &mut bus).unwrap();
    assert!(g.armed());
    let n = bus.writes.len();
    g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
    let want = program::HALT.map(|op| match op {
        Op::Write(a, v) => (a, v),
        _ => unreachable!(),
    });
    assert_eq!(&bus.writes[n..], &want, "the halt, with no wait in it");
    assert!(!g.armed());
}

/// A halt leaves a high pulse high (the counter frozen under it) and the
/// tick that comes after its whole width forces STEP low: no handler
/// waits for it.
#[test]
fn a_halted_pulse_is_released_by_a_later_tick_not_waited_for() {
    let t = StepTiming { pulse: T.tick_len + 1, ..T }; // a pulse longer than a tick
    let mut g = Generator::new(0x2000_0000);
    let mut bus = Script::default();
    g.prepare(t.tick_len, &mut bus);
    g.halted_elsewhere(&t);
    let release = (program::TIM1 + program::CCMR1, program::CCMR1_HALT);
    let ticks = program::release_ticks(t.pulse, t.tick_len);
    assert_eq!(ticks, 3, "two whole ticks, and the one the halt fell in");
    for k in 1..=ticks {
        bus.writes.clear();
        g.tick(&StepPlan::default(), true, &t, &mut bus).unwrap();
        assert_eq!(bus.writes.contains(&release), k == ticks, "released at tick {k} of {ticks}: {:?}", bus.writes);
        assert!(!bus.writes.iter().any(|w| w.0 == u32::MAX), "no tick waits");
    }
}

#[test]
fn a_segment_whose_burst_is_under_way_is_not_silenced() {
    let ring = 0x2000_0000;
    let mut g = Generator::new(ring);
    let mut bus = Script::default();
    g.prepare(T.tick_len, &mut bus);
    // arm: the stream reads as stopped, TIM11 at 100 and no update, NDTR
    // full with TIM1 not yet updated; then NDTR full, the stream on, NDTR full
    bus.reads = arm_tick(100, program::RING_WORDS, 0);
    g.tick(&StepPlan::default(), false, &T, &mut bus).unwrap();
    for _ in 0..2 {
        bus.reads = write_tick(program::RING_WORDS);
        g.tick(&StepPlan::default(), false, &T, &mut bus).unwrap();
    }
    // a tick later the DMA has read slot 0 and two words of slot 1
    let w = program::BURST_WORDS;
    bus.reads = write_tick(program::RING_WORDS - w - 2);
    let before = bus.writes.len();
    g.tick(&StepPlan::default(), false, &T, &mut bus).unwrap();
    let slot = |a: u32| (a.wrapping_sub(ring) / (4 * program::BURST_WORDS)) as usize;
    let touched: Vec<usize> = bus.writes[before..].iter().map(|(a, _)| slot(*a)).collect();
    assert!(touched.contains(&0), "slot 0, read whole, is silenced");
    assert!(!touched.contains(&1), "slot 1 is mid-burst: {touched:?}");
}

/// The arm's own part runs in the tick (its register program holds only
/// there); the first window's segments are RAM writes made by the plan's
/// handler afterwards, the same writes `tick` makes in one go.
#[test]
fn an_arm_in_the_tick_leaves_its_first_window_to_the_plan() {
    let ring = 0x2000_0000;
    let in_ring = |a: u32| (ring..ring + program::RING_WORDS * 4).contains(&a);
    let p = plan(0, 3 << 16, 0, &Prev::idle(Dir::Forward), &T); // three steps (Q16)
    assert!(p.count > 0, "a window with steps in it");
    let arm_reads = arm_tick(100, program::RING_WORDS, 0);
    let prepared = || {
        let mut g = Generator::new(ring);
        let mut bus = Script::default();
        g.prepare(T.tick_len, &mut bus);
        bus.writes.clear();
        bus.reads = arm_reads.clone();
        (g, bus)
    };
    let (mut split, mut bus) = prepared();
    assert_eq!(split.begin(false, &T, &mut bus), Ok(true));
    assert!(split.armed());
    assert!(!bus.writes.iter().any(|w| in_ring(w.0)), "the tick writes no ring entry at arm");
    let armed_at = bus.writes.len();
    split.write_plan(&p, &T, &mut bus).unwrap();
    assert!(
        bus.writes[armed_at..].iter().any(|w| in_ring(w.0) && w.0 < ring + 4 * program::BURST_WORDS),
        "slot 0 written by the plan"
    );
    let (mut whole, mut whole_bus) = prepared();
    whole.tick(&p, false, &T, &mut whole_bus).unwrap();
    assert_eq!(bus.writes, whole_bus.writes, "begin and write_plan make tick's writes");
}

/// A generator whose boot probe reads NDTR `boot`, armed with NDTR
/// reading `ndtr` and TIM1's update flag `uif`; then one tick whose NDTR
/// reads `now`. Returns the lead learnt, the arm's result, the tick's, and
/// the slots the tick wrote.
fn arm_reading(boot: u32, ndtr: u32, uif: u32, now: u32) -> (u32, Result<(), Fail>, Result<(), Fail>, Vec<usize>) {
    let ring = 0x2000_0000;
    let mut g = Generator::new(ring);
    // quiet's wait for the stream, the probe's NDTR, its wait for the stream
    let mut bus = Script { reads: vec![0, boot, 0], ..Default::default() };
    g.prepare(T.tick_len, &mut bus);
    bus.reads = arm_tick(100, ndtr, uif);
    let armed = g.tick(&StepPlan::default(), false, &T, &mut bus);
    bus.reads = write_tick(now);
    let before = bus.writes.len();
    let next = g.tick(&StepPlan::default(), false, &T, &mut bus);
    let slot = |a: u32| (a.wrapping_sub(ring) / (4 * program::BURST_WORDS)) as usize;
    let mut touched: Vec<usize> = bus.writes[before..].iter().map(|(a, _)| slot(*a)).collect();
    touched.dedup();
    (g.ndtr_lead(), armed, next, touched)
}

#[test]
fn ndtr_that_counts_the_preloaded_word_is_read_one_word_behind() {
    let (w, full) = (program::BURST_WORDS, program::RING_WORDS);
    // the manual's reading: full at boot and at arm; a burst later, one
    // slot taken and silenced
    let (lead, armed, next, touched) = arm_reading(full, full, 0, full - w);
    assert_eq!((lead, armed, next), (0, Ok(()), Ok(())));
    assert_eq!(touched.last(), Some(&0), "slot 0 taken whole and silenced, after the plan's own");
    // the preload's: one less at boot, at arm, and a burst later; the
    // same slot is taken, and it is not late
    let (lead, armed, next, preload_touched) = arm_reading(full - 1, full - 1, 0, full - w - 1);
    assert_eq!((lead, armed, next), (1, Ok(()), Ok(())));
    assert_eq!(preload_touched, touched);
}

#[test]
fn an_arm_whose_ndtr_is_not_what_the_boot_learnt_waits_for_the_next_tick() {
    let full = program::RING_WORDS;
    // a request served at arm (one left pending, say) on silicon that
    // counts transfers: it must not pass for the preload's lead
    assert_eq!(arm_reading(full, full - 1, 0, full).1, Err(Fail::ArmLate));
    // the preload not yet counted at arm where the boot saw it counted
    assert_eq!(arm_reading(full - 1, full, 0, full).1, Err(Fail::ArmLate));
    // TIM1 updated before the read: a request may have moved NDTR
    assert_eq!(arm_reading(full, full, 1, full).1, Err(Fail::ArmLate));
    // nothing but a request moves NDTR by two: no lead, and no arm
    let (lead, armed, ..) = arm_reading(full - 2, full - 2, 0, full);
    assert_eq!((lead, armed), (0, Err(Fail::ArmLate)));
}

#[test]
fn the_boot_probe_runs_the_stream_with_tim1_stopped_and_no_request_enabled_then_stops_it() {
    let mut g = Generator::new(0x2000_0000);
    let mut bus = Script::default();
    g.prepare(T.tick_len, &mut bus);
    let writes = |addr: u32| bus.writes.iter().filter(|w| w.0 == addr).map(|w| w.1).collect::<Vec<_>>();
    let tim1 = |off: u32| writes(program::TIM1 + off);
    assert_eq!(tim1(program::DIER), [0], "no DMA request enabled");
    assert!(tim1(program::CR1).iter().all(|v| v & 1 == 0), "TIM1 never counting");
    assert_eq!(writes(program::S5CR).last().map(|v| v & program::DMA_EN), Some(0), "the stream left off");
    let on = bus.writes.iter().position(|w| w.0 == program::S5CR && w.1 & program::DMA_EN != 0).unwrap();
    assert!(bus.writes[on..].iter().any(|w| w.0 == u32::MAX && w.1 >= PROBE_WAIT), "it waits for the preload");
}

#[test]
fn after_a_halt_each_tick_silences_a_share_and_the_ring_is_silent_before_it_re_arms() {
    let mut g = Generator::new(0x2000_0000);
    let mut bus = Script::default();
    g.prepare(T.tick_len, &mut bus);
    bus.reads = arm_tick(0, program::RING_WORDS, 0);
    g.tick(&StepPlan::default(), false, &T, &mut bus).unwrap();
    g.halted_elsewhere(&T); // the E-stop interrupt halted it
                            // ARR, RCR and CCR1 of each entry: PSC stays 0 from the first fill,
                            // CCR2 a DIR level that moves nothing without a step
    let share = SILENCE_PER_TICK * 3;
    let ticks = RING_ENTRIES / SILENCE_PER_TICK;
    let mut silenced = std::collections::BTreeSet::new();
    for k in 0..ticks {
        bus.writes.clear();
        g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
        // (the ring's words; the halted pulse's release is TIM1's)
        bus.writes.retain(|w| (0x2000_0000..0x2002_0000).contains(&w.0));
        assert_eq!(bus.writes.len(), share, "tick {k}: one share, not the whole ring");
        silenced.extend(bus.writes.iter().copied());
    }
    // exactly ARR, RCR and CCR1 of every entry of the ring, as a filler's
    let f = Entry::filler();
    let want: std::collections::BTreeSet<(u32, u32)> = (0..RING_ENTRIES as u32)
        .flat_map(|i| {
            [(1, f.arr), (2, f.rcr), (3, f.ccr1)].map(|(w, v)| (0x2000_0000 + (i * program::BURST_WORDS + w) * 4, v))
        })
        .collect();
    assert_eq!(silenced, want);
    bus.writes.clear();
    g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
    assert!(bus.writes.is_empty(), "silent: nothing more to do");
    // released halfway through a silence: no arm until the ring is silent
    g.halted_elsewhere(&T);
    g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
    assert_eq!(g.tick(&StepPlan::default(), false, &T, &mut bus), Err(Fail::ArmLate));
    assert!(!g.armed());
}

/// If the tick stops writing while TIM1 and the DMA run on, what is not
/// yet silenced (at most `PENDING_MAX` entries ahead of the DMA, the one
/// under way and a tick's segments) goes out, then fillers: the rest of
/// the ring must outlast the watchdog's longest period (the slowest LSI,
/// `iwdg`) before an old segment could come round.
#[test]
fn fillers_outlast_the_watchdog() {
    let fillers = (RING_ENTRIES - PENDING_MAX - 1 - entries::MAX_SEGMENTS) as u64;
    let silent_us = fillers * Entry::filler().cycles() as u64 * 1_000_000 / 96_000_000;
    let watchdog_us = crate::iwdg::period_us(crate::iwdg::WATCHDOG_US, crate::iwdg::LSI_MIN_HZ) as u64;
    assert!(silent_us > watchdog_us + 1_000_000, "{fillers} fillers, {silent_us} µs, watchdog {watchdog_us} µs");
}

/// An arm is two register programs: after a halt, `quiet` in one tick and
/// `arm` in the next, so that no tick pays for both (the boot's `prepare`
/// quietens, so the first arm is one tick). The quietening tick writes no
/// ring entry and arms nothing; its plan is not emitted.
#[test]
fn after_a_halt_the_arm_quietens_in_one_tick_and_arms_in_the_next() {
    let ring = 0x2000_0000;
    let writes = |ops: &[Op]| ops.iter().filter(|op| matches!(op, Op::Write(..))).count();
    let mut g = Generator::new(ring);
    let mut bus = Script::default();
    g.prepare(T.tick_len, &mut bus);
    g.halted_elsewhere(&T);
    while !g.silent {
        g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
    }
    for _ in 0..program::release_ticks(T.pulse, T.tick_len) {
        g.tick(&StepPlan::default(), true, &T, &mut bus).unwrap();
    }
    bus.writes.clear();
    assert_eq!(g.begin(false, &T, &mut bus), Ok(false), "quietened, not armed");
    assert!(!g.armed());
    assert_eq!(bus.writes.len(), writes(&program::quiet(T.tick_len, 0)), "quiet's writes alone: {:?}", bus.writes);
    bus.writes.clear();
    bus.reads = vec![100, 0, program::RING_WORDS, 0];
    assert_eq!(g.begin(false, &T, &mut bus), Ok(true), "armed the tick after");
    assert!(!bus.writes.iter().any(|w| w.0 == program::TIM1 + program::EGR), "no quieting (its UG) in the arming tick");
    assert!(!bus.writes.iter().any(|w| (ring..ring + program::RING_WORDS * 4).contains(&w.0)), "no ring entry");
}

/// An armed generator (its ring's slot 0 next to write) and the plan of a
/// window with steps in it.
fn armed_with_a_plan() -> (Generator, Script, StepPlan) {
    let mut g = Generator::new(0x2000_0000);
    let mut bus = Script::default();
    g.prepare(T.tick_len, &mut bus);
    bus.reads = vec![100, 0, program::RING_WORDS, 0, program::RING_WORDS, 1];
    assert_eq!(g.begin(false, &T, &mut bus), Ok(true));
    let p = plan(0, 3 << 16, 0, &Prev::idle(Dir::Forward), &T);
    assert!(p.count > 0);
    (g, bus, p)
}

/// The DMA asks for a window's first segment well before the others (the
/// tick before ends its last segment late, `entries::late_boundary`): a
/// write that the DMA catches up with once its first segment is in place
/// is in time, and loses nothing.
#[test]
fn a_write_the_dma_reaches_after_its_first_segment_is_in_place_is_in_time() {
    let (mut g, mut bus, p) = armed_with_a_plan();
    let (full, w) = (program::RING_WORDS, program::BURST_WORDS);
    // NDTR before, the stream on, NDTR after the first segment (not yet
    // asked for), NDTR at the end (its burst taken meanwhile)
    bus.reads = vec![full, 1, full, full - w];
    assert_eq!(g.write_plan(&p, &T, &mut bus), Ok(()));
    assert!(g.armed());
}

/// One the DMA asked for before it was written halts: the window went out
/// without it.
#[test]
fn a_first_segment_the_dma_asked_for_before_it_was_written_halts() {
    let (mut g, mut bus, p) = armed_with_a_plan();
    let full = program::RING_WORDS;
    // its burst under way by the time the first segment was written
    bus.reads = vec![full, 1, full - 1, full - 1];
    let before = bus.writes.len();
    assert_eq!(g.write_plan(&p, &T, &mut bus), Err(Fail::Late));
    assert!(!g.armed());
    // halted at once: no entry written after the first
    let ring = 0x2000_0000..0x2000_0000 + program::RING_WORDS * 4;
    let entry = program::BURST_WORDS * 4;
    let later = bus.writes[before..].iter().filter(|w| ring.contains(&w.0) && w.0 >= ring.start + entry).count();
    assert_eq!(later, 0, "{:?}", &bus.writes[before..]);
}

/// Each entry's CCR1 is written after its other words: a burst that reads
/// an entry half written (the writer pre-empted between its words) takes
/// the silenced slot's CCR1, no step, never a pulse with an old DIR.
#[test]
fn each_entrys_ccr1_is_written_last() {
    let (mut g, mut bus, p) = armed_with_a_plan();
    let full = program::RING_WORDS;
    bus.reads = vec![full, 1, full, full];
    let before = bus.writes.len();
    g.write_plan(&p, &T, &mut bus).unwrap();
    let entry = program::BURST_WORDS * 4;
    let mut slots = std::collections::BTreeMap::<u32, Vec<u32>>::new();
    for (a, _) in &bus.writes[before..] {
        if let Some(off) = a.checked_sub(0x2000_0000).filter(|o| *o < full * 4) {
            slots.entry(off / entry).or_default().push(off % entry);
        }
    }
    assert!(!slots.is_empty());
    for (slot, words) in slots {
        assert_eq!(words.last(), Some(&12), "slot {slot}: {words:?}");
    }
}

/// As does one whose second segment the DMA asked for before the write
/// ended: the window itself had begun.
#[test]
fn a_write_still_going_when_its_window_begins_halts() {
    let (mut g, mut bus, p) = armed_with_a_plan();
    let (full, w) = (program::RING_WORDS, program::BURST_WORDS);
    let segments = Layout::armed(Dir::Forward).segments(&p, &T, MIN_SEGMENT).len();
    assert!(segments >= 2, "a window of {segments} segments");
    bus.reads = vec![full, 1, full, full - w - 1];
    assert_eq!(g.write_plan(&p, &T, &mut bus), Err(Fail::Late));
}
