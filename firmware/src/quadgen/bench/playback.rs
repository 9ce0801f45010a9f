//! What the lathe-encoder input sees of the generator, in time: each
//! period's two edges at their compare matches and the index between them
//! (`Period::edge_offsets`, `Edges::index_in`), the update interrupt's work
//! done at each update event. For the host: the self-test's scenarios and
//! the fake board of `polyturn device` play the real generator with it.

use super::BenchGenerator;
use crate::quadgen::{program, Motion};

/// One thing TIM3 sees, at a TIM9 cycle (from the start program).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// an edge on A (forward) or B (reverse): one count, ±1
    Count(i8),
    /// the index rises: TIM3_CH3 latches the count
    Index,
}

pub struct Playback {
    gen: BenchGenerator,
    next_update: u64,
    finishing: bool,
    pending: heapless::Deque<(u64, Event), 4>,
}

impl Playback {
    pub fn new(gen: BenchGenerator) -> Playback {
        Playback { gen, next_update: 0, finishing: false, pending: heapless::Deque::new() }
    }

    pub fn generator(&self) -> &BenchGenerator {
        &self.gen
    }

    /// Every event up to TIM9 cycle `until`, in order, to `f`.
    pub fn play(&mut self, until: u64, mut f: impl FnMut(u64, Event)) {
        loop {
            if self.pending.is_empty() && self.next_update <= until && self.gen.running() {
                self.update();
            }
            match self.pending.front() {
                Some(&(at, e)) if at <= until => {
                    self.pending.pop_front();
                    f(at, e);
                }
                _ => return,
            }
        }
    }

    /// One update event: the period that starts, its events queued.
    fn update(&mut self) {
        let p = self.gen.current();
        let index = self.gen.ledger().index_in(&p);
        let ops = self.gen.on_update();
        self.gen.prepare();
        let at = self.next_update;
        self.next_update += p.clocks() as u64;
        if self.finishing || p.motion == Motion::Idle {
            self.finishing |= ops.contains(&program::FINISH);
            return;
        }
        self.finishing = ops.contains(&program::FINISH);
        let [a, b] = p.edge_offsets().map(|o| at + o as u64);
        let d = if p.motion == Motion::Forward { 1 } else { -1 };
        let _ = self.pending.push_back((a, Event::Count(d)));
        if index {
            let _ = self.pending.push_back(((a + b) / 2, Event::Index));
        }
        let _ = self.pending.push_back((b, Event::Count(d)));
    }
}
