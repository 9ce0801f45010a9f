//! The self-test's lathe-encoder generator (`polyturn_firmware::quadgen`)
//! on the model of TIM9 written from RM0383, its A/B pins decoded by the
//! model of TIM3's encoder interface (§13.3.12, Table 53) and its index
//! latched by TIM3's channel 3 (§13.3.5): the firmware's own programs, the
//! update interrupt run at a latency drawn from a range, and the decoded
//! count compared with the generator's books at every update event.

use polyturn_firmware::quadgen::program::{self as prog, apply, Bus, Op};
use polyturn_firmware::quadgen::{self as qg, Generator, Motion, Profile, Segment};
use polyturn_stm32_model::encoder::{Counting, Encoder};
use polyturn_stm32_model::{addr, Mcu, Params, PinId};

/// CK_INT cycles per bus access of the interrupt.
const ACCESS: u64 = 2;

/// Ramp up, hold, reverse at once, ramp through zero (idle periods), hold.
fn profile(rpm: i32) -> [Segment; 5] {
    [
        Segment::Ramp { from: 0, to: rpm, ms: 60 },
        Segment::Hold { rpm, ms: 20 },
        Segment::Hold { rpm: -rpm, ms: 20 },
        Segment::Ramp { from: -rpm, to: rpm / 2, ms: 60 },
        Segment::Hold { rpm: rpm / 2, ms: 10 },
    ]
}

/// The interrupt's bus: `ACCESS` cycles a write; GPIOA_BSRR, which the
/// model does not have, is the index pin, recorded with its cycle.
struct IsrBus<'a> {
    mcu: &'a mut Mcu,
    index: &'a mut Vec<(u64, bool)>,
}

impl Bus for IsrBus<'_> {
    fn write(&mut self, a: u32, v: u32) {
        self.mcu.run_until(self.mcu.cycle() + ACCESS);
        if a == prog::GPIOA_BSRR {
            let level = v & (1 << prog::INDEX_PIN) != 0;
            assert_ne!(level, v & (1 << (16 + prog::INDEX_PIN)) != 0, "BSRR sets and resets PA4");
            self.index.push((self.mcu.cycle(), level));
        } else {
            self.mcu.write(a, v);
        }
    }
    fn read(&mut self, a: u32) -> u32 {
        self.mcu.run_until(self.mcu.cycle() + ACCESS);
        self.mcu.read(a)
    }
    fn delay(&mut self, c: u32) {
        self.mcu.run_until(self.mcu.cycle() + c as u64);
    }
}

/// One update event of a running period, as the books saw it.
struct Update {
    cycle: u64,
    /// the books' count before this period
    position: i64,
    period: qg::Period,
    /// the count TIM3 must latch if the index rises in this period
    index: Option<i64>,
}

/// What happened on the pins.
struct Run {
    mcu: Mcu,
    updates: Vec<Update>,
    index: Vec<(u64, bool)>,
    books: i64,
}

/// Plays `segs` at `cpr`: the start program, then at every TIM9 update
/// event the interrupt after `latency(k)` cycles; `patch` may alter every
/// program before it is applied.
fn run(cpr: u32, segs: &[Segment], latency: impl Fn(u64) -> u64, patch: impl Fn(&mut Vec<Op>)) -> Run {
    let profile = Profile::new(cpr, segs).unwrap();
    let (mut gen, init) = Generator::start(&profile, profile.periods()).unwrap();
    let (mut mcu, mut index, mut updates) = (Mcu::new(Params::default()), Vec::new(), Vec::new());
    let mut ops = init.to_vec();
    patch(&mut ops);
    apply(&ops, &mut IsrBus { mcu: &mut mcu, index: &mut index }).unwrap();
    while gen.running() {
        assert!(mcu.run_to_tim9_update(mcu.cycle() + 10_000_000), "no update event");
        let u = mcu.cycle();
        if mcu.read(addr::TIM9_CR1) & 1 != 0 {
            let (period, position) = (gen.current(), gen.ledger().position());
            updates.push(Update { cycle: u, position, period, index: gen.ledger().index_count(&period) });
        }
        let k = updates.len() as u64;
        mcu.run_until(u + latency(k).max(ACCESS) - ACCESS);
        let mut ops = gen.on_update().to_vec();
        patch(&mut ops);
        apply(&ops, &mut IsrBus { mcu: &mut mcu, index: &mut index }).unwrap();
        // the handler's last work, for the next update event
        gen.prepare();
    }
    mcu.run_until(mcu.cycle() + 1_000_000);
    Run { books: gen.ledger().position(), mcu, updates, index }
}

/// A latency drawn (xorshift, repeatable) from `lo..=hi`.
fn jitter(lo: u64, hi: u64) -> impl Fn(u64) -> u64 {
    move |k| {
        let mut x = k.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        lo + x % (hi - lo + 1)
    }
}

/// An event on the encoder's inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Input {
    A(bool),
    B(bool),
    Index(bool),
}

/// The pins' changes in time order (the index after A/B in the same cycle).
fn timeline(r: &Run) -> Vec<(u64, Input)> {
    let mut t: Vec<(u64, Input)> = r
        .mcu
        .edges()
        .iter()
        .map(|e| (e.cycle, if e.pin == PinId::Pa2 { Input::A(e.high) } else { Input::B(e.high) }))
        .collect();
    assert!(r.mcu.edges().iter().all(|e| matches!(e.pin, PinId::Pa2 | PinId::Pa3)));
    let mut level = false;
    for &(c, l) in &r.index {
        if l != level {
            t.push((c, Input::Index(l)));
            level = l;
        }
    }
    t.sort_by_key(|&(c, i)| (c, matches!(i, Input::Index(_))));
    t
}

/// What TIM3 made of it.
#[derive(Debug, Default)]
struct Decoded {
    /// update events where TIM3's count differed from the books
    wrong_counts: Vec<(usize, i64, i64)>,
    /// A and B edges in the same cycle (Table 53 does not define them)
    together: usize,
    /// the counts TIM3 latched at the index
    latched: Vec<i64>,
    /// closest A/B edges, and closest index edge to an A/B edge, cycles
    min_gap: u64,
    index_margin: u64,
    final_count: i64,
}

fn decode(r: &Run) -> Decoded {
    let mut enc = Encoder::new(Counting::Both, 0xFFFF, [false; 3]);
    let (mut a, mut b) = (false, false);
    let mut d = Decoded { min_gap: u64::MAX, index_margin: u64::MAX, ..Decoded::default() };
    let (mut next_update, mut last_ab, mut last_index) = (0, None::<u64>, None::<u64>);
    let check = |d: &mut Decoded, enc: &Encoder, k: usize, u: &Update| {
        if enc.position() != u.position {
            d.wrong_counts.push((k, enc.position(), u.position));
        }
    };
    for &(c, input) in &timeline(r) {
        while next_update < r.updates.len() && r.updates[next_update].cycle < c {
            check(&mut d, &enc, next_update, &r.updates[next_update]);
            next_update += 1;
        }
        match input {
            Input::A(l) | Input::B(l) => {
                if let Some(prev) = last_ab {
                    d.together += (prev == c) as usize;
                    d.min_gap = d.min_gap.min(c - prev);
                }
                if let Some(i) = last_index {
                    d.index_margin = d.index_margin.min(c - i);
                }
                (a, b) = if matches!(input, Input::A(_)) { (l, b) } else { (a, l) };
                enc.input(a, b);
                last_ab = Some(c);
            }
            Input::Index(l) => {
                enc.index(l);
                if let Some(captured) = enc.take_capture() {
                    d.latched.push(captured as i16 as i64);
                }
                d.index_margin = d.index_margin.min(c - last_ab.unwrap_or(0));
                last_index = Some(c);
            }
        }
    }
    for (k, u) in r.updates.iter().enumerate().skip(next_update) {
        check(&mut d, &enc, k, u);
    }
    d.final_count = enc.position();
    d
}

/// The books' index rises: a period whose index is high after one that was not.
fn rises(r: &Run) -> Vec<i64> {
    let mut prev = false;
    r.updates
        .iter()
        .filter_map(|u| {
            let rise = u.index.is_some() && !prev;
            prev = u.index.is_some();
            rise.then(|| u.index.unwrap())
        })
        .collect()
}

fn assert_exact(name: &str, r: &Run) -> Decoded {
    let d = decode(r);
    assert!(
        d.wrong_counts.is_empty(),
        "{name}: TIM3 count vs books (update, TIM3, books): {:?}",
        &d.wrong_counts[..5.min(d.wrong_counts.len())]
    );
    assert_eq!(d.together, 0, "{name}: A and B switched together");
    assert_eq!(d.final_count, r.books, "{name}");
    assert_eq!(d.latched, rises(r), "{name}: latched index counts");
    d
}

#[test]
fn a_ramp_hold_reverse_profile_decodes_to_the_books_at_every_update() {
    // the generator's top speed at 200 counts a turn
    let mut r =
        run(200, &profile(qg::max_rpm(200) as i32), jitter(qg::ENTRY_MIN as u64, qg::LATENCY_MAX as u64), |_| {});
    let d = assert_exact("200 cpr", &r);
    assert!(r.updates.len() > 500, "{} updates", r.updates.len());
    assert!(r.updates.iter().any(|u| u.period.motion == Motion::Idle));
    assert!(r.updates.iter().any(|u| u.period.psc == qg::PSC_MAX));
    assert!(d.latched.len() >= 4, "{:?}", d.latched);
    // outputs end low, counter stopped
    assert!(!r.mcu.pa2() && !r.mcu.pa3());
    assert_eq!(r.mcu.read(addr::TIM9_CR1) & 1, 0);
    assert_eq!(r.books % 4, 0);
}

// Every A/B edge where `Period::edge_offsets` puts it, update events
// `Period::clocks` apart; edges never closer than half the fastest period.
#[test]
fn edges_land_where_the_books_say_and_never_closer_than_the_shortest_half_period() {
    let r = run(2400, &profile(qg::max_rpm(2400) as i32), jitter(100, 900), |_| {});
    let mut want = Vec::new();
    for w in r.updates.windows(2) {
        assert_eq!(w[1].cycle - w[0].cycle, w[0].period.clocks() as u64);
    }
    for u in &r.updates {
        if u.period.motion != Motion::Idle {
            want.extend(u.period.edge_offsets().map(|o| u.cycle + o as u64));
        }
    }
    let got: Vec<u64> = r.mcu.edges().iter().map(|e| e.cycle).collect();
    assert_eq!(got, want);
    let d = assert_exact("top speed", &r);
    assert!(d.min_gap >= (qg::HALF_MIN_CLOCKS - qg::PSC_MAX as u32) as u64, "{}", d.min_gap);
    // TIM3's 8-sample input filter (app::drivers) passes every edge
    assert!(d.min_gap > 8);
}

#[test]
fn a_reversal_neither_loses_nor_doubles_a_count() {
    let segs = [Segment::Hold { rpm: 300, ms: 3 }, Segment::Hold { rpm: -300, ms: 3 }];
    let r = run(2400, &segs, jitter(20, 2_000), |_| {});
    assert_exact("reversal", &r);
    let turn = r.updates.iter().position(|u| u.period.motion == Motion::Reverse).unwrap();
    let p = r.updates[turn].position;
    assert_eq!(r.updates[turn - 1].position, p - 2);
    assert_eq!(r.updates[turn + 1].position, p - 2);
    // the same two counts back, edge by edge: A, B, then B, A
    let pins: Vec<PinId> = r.mcu.edges().iter().map(|e| e.pin).collect();
    assert_eq!(pins[2 * turn - 2..2 * turn + 2], [PinId::Pa2, PinId::Pa3, PinId::Pa3, PinId::Pa2]);
}

// The index rises between a period's two edges with `MARGIN` to spare at
// the fastest and at the slowest interrupt the bound allows: TIM3 latches
// n·cpr + 1 both ways, one revolution apart.
#[test]
fn the_index_is_latched_every_cpr_counts_at_both_ends_of_the_latency_bound() {
    for lat in [qg::ENTRY_MIN as u64, qg::LATENCY_MAX as u64] {
        let cpr = 20;
        let rpm = qg::max_rpm(cpr) as i32;
        let r = run(cpr, &profile(rpm), |_| lat, |_| {});
        let d = assert_exact(&format!("latency {lat}"), &r);
        assert!(d.index_margin >= qg::MARGIN as u64, "latency {lat}: margin {}", d.index_margin);
        assert!(d.latched.len() > 50, "{} index pulses", d.latched.len());
        assert!(d.latched.iter().all(|c| c.rem_euclid(cpr as i64) == 1), "{:?}", d.latched);
        let steps: Vec<i64> = d.latched.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(steps.iter().all(|s| s.abs() == cpr as i64 || *s == 0), "{steps:?}");
    }
}

// The bound is needed: an interrupt later than half the fastest period
// raises the index after the period's second edge (here halfway to the
// next update event, so the next period's values still come in time).
#[test]
fn an_index_later_than_the_bound_latches_the_wrong_count() {
    let late = 3 * qg::HALF_MIN_CLOCKS as u64 / 2;
    let r = run(40, &[Segment::Hold { rpm: qg::max_rpm(40) as i32, ms: 5 }], |_| late, |_| {});
    let d = decode(&r);
    assert!(d.wrong_counts.is_empty());
    assert!(!d.latched.is_empty() && d.latched.iter().all(|c| c.rem_euclid(40) == 2), "{:?}", d.latched);
}

/// Every write to `reg` passed through `f`.
fn patch_reg(reg: u32, f: impl Fn(u32) -> u32) -> impl Fn(&mut Vec<Op>) {
    move |ops| {
        for op in ops.iter_mut() {
            if let Op::Write(a, v) = op {
                if *a == reg {
                    *v = f(*v);
                }
            }
        }
    }
}

// Broken on purpose: without the CCR preload (OC1PE = OC2PE = 0) the
// interrupt's new compare values act mid-period, and counts go wrong.
#[test]
fn without_ccr_preload_the_count_goes_wrong() {
    let no_preload = patch_reg(prog::CCMR1, |v| v & !((1 << 3) | (1 << 11)));
    let r = run(2400, &profile(300), jitter(100, 2_000), no_preload);
    let d = decode(&r);
    assert!(!d.wrong_counts.is_empty() || d.together > 0 || d.final_count != r.books);
}

// Broken on purpose: CCR2 one tick late moves every B edge (the count
// still agrees: the edge check is what catches it).
#[test]
fn a_wrong_ccr2_moves_the_edges() {
    let r = run(2400, &profile(300), jitter(100, 900), patch_reg(prog::CCR2, |v| if v < 0xFFFF { v + 1 } else { v }));
    let mut want = Vec::new();
    for u in r.updates.iter().filter(|u| u.period.motion != Motion::Idle) {
        want.extend(u.period.edge_offsets().map(|o| u.cycle + o as u64));
    }
    let got: Vec<u64> = r.mcu.edges().iter().map(|e| e.cycle).collect();
    assert_ne!(got, want);
}

// `STOP` mid-run: the counter stops, no output moves after it.
#[test]
fn stop_freezes_both_outputs() {
    let profile = Profile::new(2400, &[Segment::Hold { rpm: 300, ms: 10 }]).unwrap();
    let (mut gen, init) = Generator::start(&profile, profile.periods()).unwrap();
    let (mut mcu, mut index) = (Mcu::new(Params::default()), Vec::new());
    apply(&init, &mut IsrBus { mcu: &mut mcu, index: &mut index }).unwrap();
    for _ in 0..7 {
        mcu.run_to_tim9_update(u64::MAX);
        apply(&gen.on_update(), &mut IsrBus { mcu: &mut mcu, index: &mut index }).unwrap();
    }
    mcu.run_until(mcu.cycle() + 3_000);
    apply(&prog::STOP, &mut IsrBus { mcu: &mut mcu, index: &mut index }).unwrap();
    let (n, levels) = (mcu.edges().len(), (mcu.pa2(), mcu.pa3()));
    mcu.run_until(mcu.cycle() + 1_000_000);
    assert_eq!((mcu.edges().len(), (mcu.pa2(), mcu.pa3())), (n, levels));
    assert!(!index.last().unwrap().1, "index left high");
}
