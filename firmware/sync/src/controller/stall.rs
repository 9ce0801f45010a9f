//! A settings save stalls the CPU for up to 2 s: the flash erase stops
//! every fetch from flash, so no tick runs (RM0383 §3.5: a read of flash
//! while it is erased stalls the bus). The lathe's encoder keeps counting
//! in hardware meanwhile (TIM3), but its 16-bit counter can wrap, and the
//! index is latched only once (TIM3_CH3 capture). So the tick after the
//! stall must not take a jump as a fault nor an index as a slip, and the
//! save's reply must say whether the lathe's count survived.

use super::Controller;

/// What the lathe did while the CPU was stalled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stall {
    /// no count moved
    #[default]
    Still,
    /// it turned less than a tick's plausible jump: counted exactly
    Counted,
    /// it turned further than the counter can tell: the gear is re-based on
    /// the counter; `reindexed` if an index was latched meanwhile (the
    /// phase reference is that index again), else the phase to earlier
    /// cuts is lost
    Lost { reindexed: bool },
}

impl Stall {
    pub fn describe(self) -> &'static str {
        match self {
            Stall::Still => "",
            Stall::Counted => " (the lathe turned during the save: counted)",
            Stall::Lost { reindexed: true } => {
                " (the lathe turned during the save, too far to count: the phase is re-referenced to the index)"
            }
            Stall::Lost { reindexed: false } => {
                " (the lathe turned during the save, too far to count: the phase to earlier cuts is lost)"
            }
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Watch {
    outcome: Stall,
    indexed: bool,
}

impl Controller {
    /// Called (under the lock) just before the flash is erased.
    pub fn begin_stall(&mut self) {
        self.stall = Some(Watch::default());
    }

    /// Called after the save: re-bases what the stall made uncertain and
    /// says what happened.
    pub fn end_stall(&mut self) -> Stall {
        let Some(w) = self.stall.take() else { return Stall::Still };
        // ticks were lost: the instants the edge timer counts are off until
        // the board measures them again (`start_edges`)
        self.edges = None;
        if let Stall::Lost { reindexed } = w.outcome {
            if reindexed {
                self.origin = self.index.reference().unwrap_or(self.origin);
            }
            self.rebase_pending = false;
            // the speed over the stall is not known: start measuring afresh
            self.est = crate::estimator::Estimator::new(self.d.still_ticks);
            self.rebase();
        }
        w.outcome
    }

    /// In the tick: a jump beyond a tick's plausible count during a stall
    /// is the stall's, not a fault. True if absorbed.
    pub(super) fn stall_jump(&mut self, delta: i32) -> bool {
        let Some(w) = &mut self.stall else { return false };
        if delta.abs() > self.d.max_counts_per_tick {
            w.outcome = Stall::Lost { reindexed: w.indexed };
        } else if delta != 0 && w.outcome == Stall::Still {
            w.outcome = Stall::Counted;
        }
        true
    }

    /// In the tick: an index latched during a stall starts a new reference
    /// (the count since the last one is not known). True if taken here.
    pub(super) fn stall_index(&mut self, raw: u16) -> bool {
        let Some(w) = &mut self.stall else { return false };
        w.indexed = true;
        if let Stall::Lost { .. } = w.outcome {
            w.outcome = Stall::Lost { reindexed: true };
        }
        self.index = Default::default();
        self.on_index(raw);
        true
    }
}
