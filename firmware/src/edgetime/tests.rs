//! The edge times' words and the tick's read against a scripted bus (the model runs the
//! same words on RM0383's timers: `firmware/stm32-model/tests/edgetime.rs`).

use super::program::{Bus, Op, CONFIG};
use super::read::{lathe, Gate};
use super::*;
use polyturn_sync::edges::EdgeRegs;
use std::collections::{HashMap, VecDeque};

/// Each address reads its queued values in turn, then its last one again;
/// every access is logged.
#[derive(Default)]
pub(super) struct Script {
    queued: HashMap<u32, VecDeque<u32>>,
    last: HashMap<u32, u32>,
    pub(super) log: Vec<(char, u32, u32)>,
}

impl Script {
    pub(super) fn with(mut self, addr: u32, values: &[u32]) -> Script {
        self.queued.entry(addr).or_default().extend(values);
        self
    }
    pub(super) fn reads_of(&self, addr: u32) -> usize {
        self.log.iter().filter(|l| l.0 == 'r' && l.1 == addr).count()
    }
    pub(super) fn writes(&self) -> Vec<Op> {
        self.log.iter().filter(|l| l.0 == 'w').map(|l| Op::Write(l.1, l.2)).collect()
    }
}

impl Bus for Script {
    fn write(&mut self, addr: u32, value: u32) {
        self.log.push(('w', addr, value));
    }
    fn read(&mut self, addr: u32) -> u32 {
        let next = self.queued.get_mut(&addr).and_then(|q| q.pop_front());
        let v = next.unwrap_or_else(|| self.last.get(&addr).copied().unwrap_or(0));
        self.last.insert(addr, v);
        self.log.push(('r', addr, v));
        v
    }
    fn delay(&mut self, cycles: u32) {
        self.log.push(('d', 0, cycles));
    }
}

pub(super) const STAMP: u32 = TIM5 + off::CCR3;
pub(super) const COUNT: u32 = TIM3 + off::CCR1;
pub(super) const CNT3: u32 = TIM3 + off::CNT;
pub(super) const CNT5: u32 = TIM5 + off::CNT;

#[test]
fn the_configuration_words_are_the_manuals_bits() {
    let w = |a: u32| CONFIG.iter().position(|op| matches!(op, Op::Write(x, _) if *x == a)).unwrap();
    let word = |a: u32| match CONFIG[w(a)] {
        Op::Write(_, v) => v,
        _ => unreachable!(),
    };
    assert_eq!(word(TIM5 + off::SMCR), 0x0010, "TS = 001 (ITR1), SMS = 000");
    assert_eq!(word(TIM5 + off::CCMR2), 0x0003, "CC3S = 11: IC3 on TRC");
    assert_eq!(word(TIM5 + off::CCER), 0x0100, "CC3E, rising");
    assert_eq!(word(TIM3 + off::SMCR), 0x0003, "encoder mode 3");
    assert_eq!(word(TIM3 + off::CCMR1), 0x3131, "CC1S = CC2S = 01, IC1F = IC2F = 0011");
    assert_eq!(word(TIM3 + off::CCMR2), 0x0031, "CC3S = 01, IC3F = 0011");
    assert_eq!(word(TIM3 + off::CCER), 0x0111, "CC1E, CC2E, CC3E, all rising");
    assert_eq!(word(TIM3 + off::CR2), 0x0030, "MMS = 011, compare pulse");
    assert_eq!(word(TIM3 + off::SR), 0x1C5D, "CC1IF and CC1OF cleared, the rest written 1");
    // TS before the channel; CC3S before CC3E; TIM5 before TIM3's pulse;
    // CC1IF cleared after it
    assert!(w(TIM5 + off::SMCR) < w(TIM5 + off::CCMR2) && w(TIM5 + off::CCMR2) < w(TIM5 + off::CCER));
    assert!(w(TIM5 + off::CCER) < w(TIM3 + off::CR2) && w(TIM3 + off::CR2) < w(TIM3 + off::SR));
}

#[test]
fn nothing_of_embassys_tim5_is_written() {
    for op in CONFIG {
        let Op::Write(a, _) = op else { panic!("{op:?}") };
        if (TIM5..TIM5 + 0x400).contains(&a) {
            assert!([off::SMCR, off::CCMR2, off::CCER].contains(&(a - TIM5)), "{a:#x}");
        }
    }
}

#[test]
fn a_closed_gate_reads_the_count_alone_and_opens_at_cc1if() {
    let mut bus = Script::default().with(CNT3, &[77]);
    for gate in [Gate::Off, Gate::Waiting] {
        assert_eq!(lathe(gate, &mut bus), (77, None));
    }
    assert_eq!((bus.reads_of(COUNT), bus.reads_of(STAMP)), (0, 0), "CCR1 unread: CC1IF stays");
    let mut g = Gate::Waiting;
    g.note(program::CC3IF);
    assert_eq!(g, Gate::Waiting, "the index is not a timed edge");
    g.note(program::CC1IF);
    assert_eq!(g, Gate::Open);
    let mut off = Gate::Off;
    off.note(program::CC1IF);
    assert_eq!(off, Gate::Off, "untimed stays untimed");
}

#[test]
fn the_pair_is_read_between_two_equal_stamps_with_the_count_between() {
    let mut bus = Script::default().with(STAMP, &[500, 500]).with(COUNT, &[41]).with(CNT3, &[42]);
    assert_eq!(lathe(Gate::Open, &mut bus), (42, Some(EdgeRegs { count: 41, stamp: 500 })));
    let order: Vec<u32> = bus.log.iter().map(|l| l.1).collect();
    assert_eq!(order, [STAMP, COUNT, CNT3, STAMP], "the count read two reads before the stamp");
}

#[test]
fn an_edge_between_the_stamps_is_read_again_and_a_third_gives_none() {
    let mut bus = Script::default().with(STAMP, &[500, 540, 540]).with(COUNT, &[41, 45]).with(CNT3, &[44]);
    assert_eq!(lathe(Gate::Open, &mut bus), (44, Some(EdgeRegs { count: 45, stamp: 540 })));
    let mut racing = Script::default().with(STAMP, &[500, 540, 580]).with(COUNT, &[41, 45]).with(CNT3, &[44]);
    assert_eq!(lathe(Gate::Open, &mut racing), (44, None));
    assert_eq!(racing.reads_of(STAMP), 3, "bounded: one more try");
}

#[test]
fn a_and_b_are_the_pins_of_the_board() {
    let pin = |s: &str| crate::board::PINS.iter().find(|p| p.signal == s).unwrap().port_and_index();
    assert_eq!(pin("LATHE_A"), ('A', A_PIN as u8));
    assert_eq!(pin("LATHE_B"), ('A', B_PIN as u8));
    // a tick is a whole number of stamps
    assert_eq!(u32::from(STAMPS_PER_TICK) * TICK_HZ, STAMP_HZ);
}
