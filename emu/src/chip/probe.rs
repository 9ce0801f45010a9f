//! What the checks watch at exception entry and return: the tick's handler clearing
//! UIF, the EXTI15_10 handler's entry time and the outputs when it returns, a pin
//! change fired right after a tick returns, and the step plan's handler (its time,
//! and a stall inside it).

use super::pins::Outputs;
use super::Chip;
use crate::svd;
use polyturn_stm32_model::addr::{off, TIM11, TIM1_CR1};
use polyturn_stm32_model::bits::ccmr;

/// A pin change to fire after the next tick returns: (port, pin, level).
pub type Trip = (usize, u8, Option<bool>);

#[derive(Default)]
pub struct Probe {
    pub tick_uif_clears: u64,
    pub exti_entered: Option<u64>,
    pub exti_return: Option<Outputs>,
    pub trip: Option<Trip>,
    /// A pin change to fire right after the image writes this value to this
    /// register: (address, value, change). The E-stop opening mid-arm.
    pub trip_on_write: Option<(u32, u32, Trip)>,
    /// the first write stopping TIM1 (CR1 with CEN clear) after `edge_at`
    pub step_timer_stopped: Option<u64>,
    /// the bound's clock at `edge_at` and at `step_timer_stopped`: the
    /// cycles between them that silicon cannot exceed
    pub edge_bound: Option<u64>,
    pub stopped_bound: Option<u64>,
    pub before: Option<Outputs>,
    pub edge_at: Option<u64>,
    /// the tick handler's runs
    pub tick: Runs,
    /// the step plan's handler's runs (`board::PLAN_IRQ`)
    pub plan: Runs,
    /// CPU cycles to stall at the plan handler's first read of DMA2 stream
    /// 5's NDTR (`job::planlate`): the plan still running at the next tick
    pub stall_in_plan: Option<u64>,
    /// the self-test's index handler timed (`IndexTiming`), when a job asks
    pub index: Option<IndexTiming>,
}

/// From TIM9's update event to the self-test's index write (`quadgen`'s
/// `LATENCY_MAX` bounds it), on both clocks: the handler's first write to
/// GPIOA_BSRR after its entry (its later ones repeat the level). The event
/// falls inside a block; the bound's clock at it is taken at the start of
/// the last block that began no later (`trail`), which can only lengthen
/// the figure. A write that cannot be timed so (its event older than the
/// trail, or a second update event before it: the handler a period late)
/// is counted `untimed`, and a job fails on it.
#[derive(Default)]
pub struct IndexTiming {
    /// (model, bound) at the start of recent blocks, oldest first
    trail: std::collections::VecDeque<(u64, u64)>,
    /// the handler's entries (`Chip::entries`) and TIM9's UIF sets at the
    /// last write timed
    last_entry: u64,
    last_sets: u64,
    pub writes: u64,
    pub untimed: u64,
    pub worst_model: u64,
    pub worst_bound: u64,
}

/// Block starts kept: more than any handler's latency spans.
const TRAIL: usize = 1 << 14;

impl IndexTiming {
    fn bound_at(&self, t: u64) -> Option<u64> {
        let i = self.trail.partition_point(|&(m, _)| m <= t);
        (i > 0 && t > 0).then(|| self.trail[i - 1].1)
    }
}

impl Probe {
    /// A block starts at these (model, bound) cycles.
    pub fn trail_block(&mut self, now: u64, bound: u64) {
        if let Some(ix) = self.index.as_mut() {
            if ix.trail.len() == TRAIL {
                ix.trail.pop_front();
            }
            ix.trail.push_back((now, bound));
        }
    }
}

/// A handler's runs, from its request's entry to its return (the return's
/// own cycles included), on both clocks (`clock`): the model's time of the
/// run under way, and (count, total, worst) of each.
#[derive(Default)]
pub struct Runs {
    entered: Option<(u64, u64)>,
    pub runs: u64,
    pub total: u64,
    pub worst: u64,
    /// when the worst run (the model's) began
    pub worst_at: u64,
    /// the bound's total and worst
    pub total_bound: u64,
    pub worst_bound: u64,
    /// every run's (model start, bound) when POLYTURN_EMU_RUNS is set (a study)
    pub all: Vec<(u64, u64)>,
}

impl Runs {
    /// When the run now under way was entered (the model's cycle).
    pub fn entered(&self) -> Option<u64> {
        self.entered.map(|e| e.0)
    }

    pub fn average(&self) -> f64 {
        self.total as f64 / self.runs.max(1) as f64
    }

    pub fn average_bound(&self) -> f64 {
        self.total_bound as f64 / self.runs.max(1) as f64
    }

    fn enter(&mut self, now: (u64, u64)) {
        self.entered = Some(now);
    }

    fn leave(&mut self, now: (u64, u64)) {
        if let Some((t, tb)) = self.entered.take() {
            let (d, db) = (now.0 - t, now.1 - tb);
            if d > self.worst {
                self.worst_at = t;
            }
            (self.runs, self.total, self.worst) = (self.runs + 1, self.total + d, self.worst.max(d));
            (self.total_bound, self.worst_bound) = (self.total_bound + db, self.worst_bound.max(db));
            if std::env::var_os("POLYTURN_EMU_RUNS").is_some() {
                self.all.push((t, db));
            }
        }
    }
}

/// The tick's priority byte as the NVIC holds it (`board::TICK_LEVEL`).
pub const TICK_PRIO: u32 = (polyturn_firmware::board::TICK_LEVEL as u32) << 4;
/// The step plan's (`board::PLAN_LEVEL`).
pub const PLAN_PRIO: u32 = (polyturn_firmware::board::PLAN_LEVEL as u32) << 4;

pub fn tick_exc() -> usize {
    16 + svd::irq("TIM1_TRG_COM_TIM11")
}

pub fn plan_exc() -> usize {
    16 + svd::irq(polyturn_firmware::board::PLAN_IRQ)
}

fn tim9_exc() -> usize {
    16 + svd::irq("TIM1_BRK_TIM9")
}

fn exti_exc() -> usize {
    16 + svd::irq("EXTI15_10")
}

/// At an exception's entry, before its cost is counted.
pub fn on_enter(c: &mut Chip, exc: usize) {
    let now = (c.now, c.bound);
    if exc == tick_exc() {
        c.probe.tick.enter(now);
    }
    if exc == exti_exc() && c.probe.exti_entered.is_none() {
        c.probe.exti_entered = Some(c.now);
    }
    if exc == plan_exc() {
        c.probe.plan.enter(now);
    }
}

/// At an exception's return: its cost (held by the meter for the next
/// instruction) counted in the run.
pub fn on_return(c: &mut Chip, exc: usize) {
    let ret = crate::clock::exception::RETURN as u64;
    let now = (c.now + ret, c.bound + ret);
    if exc == tick_exc() {
        c.probe.tick.leave(now);
        if c.tape.is_some() {
            let o = c.outputs();
            let enable = o.enable.is_some_and(|e| e != o.enable_inactive);
            if let Some(t) = c.tape.as_mut() {
                t.tick_done(enable);
            }
        }
        if c.mcu.read(TIM11 + off::SR) & 1 == 0 {
            c.probe.tick_uif_clears += 1;
        }
        if let Some(t) = c.probe.trip.take() {
            fire(c, t);
        }
    } else if exc == exti_exc() && c.probe.exti_return.is_none() {
        c.probe.exti_return = Some(c.outputs());
    } else if exc == plan_exc() {
        c.probe.plan.leave(now);
    }
}

/// Before a bus read: the stall a job asked for inside the plan handler
/// (`stall_in_plan`), as a flash operation stalls the CPU, timers running;
/// the tick it lets pend is taken at the end of the block.
pub fn on_read(c: &mut Chip, word: u32) {
    if word == polyturn_firmware::stepgen::program::S5NDTR && c.active.last() == Some(&plan_exc()) {
        if let Some(cycles) = c.probe.stall_in_plan.take() {
            c.stall(cycles);
            c.update_lines();
            c.deadline = 0;
        }
    }
}

/// After a bus write: fires `trip_on_write` if this is its write. The
/// interrupt the change pends is taken at the end of the block (`fire`).
pub fn on_write(c: &mut Chip, word: u32, value: u32) {
    if word == polyturn_firmware::quadgen::program::GPIOA_BSRR && c.active.last() == Some(&tim9_exc()) {
        index_written(c);
    }
    if word == TIM1_CR1 && value & 1 == 0 && c.probe.edge_at.is_some() && c.probe.step_timer_stopped.is_none() {
        c.probe.step_timer_stopped = Some(c.now);
        c.probe.stopped_bound = Some(c.bound);
    }
    if c.probe.trip_on_write.is_some_and(|(a, v, _)| a == word && v == value) {
        if let Some((_, _, t)) = c.probe.trip_on_write.take() {
            fire(c, t);
        }
    }
}

/// Fires the input change having set the ESC to a running pulse (1.5 × the stop
/// pulse, as a running BLDC would have it, in force and waiting: CCR1 written
/// with OC1PE cleared, then set again, RM0383 §14.5.5), so the E-stop
/// interrupt's own work is visible before the next tick would redo it.
fn fire(c: &mut Chip, (port, pin, level): Trip) {
    let stop = c.outputs().esc_stop;
    let ccmr1 = c.gp[3].get(off::CCMR1);
    c.gp[3].write(off::CCMR1, ccmr1 & !ccmr::ocpe(0).mask(), 0xFFFF);
    c.gp[3].write(off::CCR1, stop * 3 / 2, 0xFFFF);
    c.gp[3].write(off::CCMR1, ccmr1, 0xFFFF);
    c.probe.before = Some(c.outputs());
    c.probe.edge_at = Some(c.now);
    c.probe.edge_bound = Some(c.bound);
    c.probe.step_timer_stopped = None;
    c.probe.stopped_bound = None;
    let edges = c.gpio[port].drive(pin, level);
    c.pin_edges(port, edges);
    c.update_lines();
    c.deadline = 0;
}

/// The self-test's handler wrote GPIOA_BSRR: its first write since it was
/// entered is the index, timed from TIM9's update event on both clocks.
fn index_written(c: &mut Chip) {
    let (at, sets) = (c.mcu.tim9_uif_at(), c.mcu.tim9_uif_sets());
    let entry = c.entries.get(&tim9_exc()).copied().unwrap_or(0);
    let (now, bound) = (c.now, c.bound);
    let Some(ix) = c.probe.index.as_mut() else { return };
    if entry == ix.last_entry {
        return; // a later write of the same run
    }
    let once = sets == ix.last_sets + 1 || ix.writes == 0;
    (ix.last_entry, ix.last_sets) = (entry, sets);
    ix.writes += 1;
    match ix.bound_at(at).filter(|_| once) {
        Some(from) => {
            ix.worst_model = ix.worst_model.max(now.saturating_sub(at));
            ix.worst_bound = ix.worst_bound.max(bound.saturating_sub(from));
        }
        None => ix.untimed += 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound's clock at an event is the last block start at or before
    /// it (never later: the latency only lengthens); an event before the
    /// trail, or none recorded (cycle 0), cannot be timed.
    #[test]
    fn an_event_is_timed_from_the_last_block_that_began_before_it() {
        let mut p = Probe { index: Some(IndexTiming::default()), ..Probe::default() };
        for (m, b) in [(10, 15), (20, 30), (30, 47)] {
            p.trail_block(m, b);
        }
        let ix = p.index.as_ref().unwrap();
        assert_eq!(
            [5, 10, 25, 30, 99, 0].map(|t| ix.bound_at(t)),
            [None, Some(15), Some(30), Some(47), Some(47), None]
        );
    }
}
