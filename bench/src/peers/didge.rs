//! Didge (prototypicall/Didge at 8fa5981, `firmware/gear.hpp`,
//! `main.cpp` L61-93, `doc/How.md`): an exact integer Bresenham on the
//! ratio N/D steps per count, advanced at each encoder edge; the timer
//! compare fires the step in hardware at the edge, delayed by T·|err|/N
//! (T the edge period, measured on A's last full cycle) so that it falls
//! where the line N/D·x crosses the step's level.
//!
//! Didge refuses N/D ≥ 1 (`verify_thread`): at most one step a count.
//! Every scenario here needs more (1.8 to 4.9 steps a count), so Didge
//! runs generalised, two ways:
//! - *with its delay*: each step delayed to where the line crosses its
//!   level, predicted from T, as Didge delays its one step a count,
//!   applied to every step whose crossing comes before the next edge
//!   (before A has a period: the Bresenham's due steps at once). On this
//!   model's exact edges that is edge timing with no tick and no stamp;
//! - *without it*: at each edge the Bresenham's due steps (round half up,
//!   `gear.hpp`) fire at once: a count-and-step Bresenham.
//!
//! Steps are at least `MIN_GAP_S` apart (its 1.2 µs pulse and 0.4 µs
//! hold, rounded up). The lathe turns one way in every scenario here:
//! counting down is not modelled.

/// Shortest step period: 1.2 µs pulse + low time.
const MIN_GAP_S: f64 = 2.5e-6;
/// A full A cycle longer than this reads as none (TIM2's timeout: 65 534
/// ticks at 18 MHz).
const TIMEOUT_S: f64 = 3.64e-3;

pub struct Didge {
    num: i64,
    den: i64,
    sense: i32,
    predict: bool,
    /// steps emitted or scheduled, in the core's sense (before `sense`)
    steps: i64,
    /// the last A rise (s) and A's last full period (s)
    last_rise: Option<f64>,
    period: Option<f64>,
    last_step: f64,
}

impl Didge {
    pub fn new(num: u64, den: u64, sense: i32, predict: bool) -> Didge {
        let (num, den) = (num as i64, den as i64);
        Didge { num, den, sense, predict, steps: 0, last_rise: None, period: None, last_step: f64::MIN }
    }

    /// An edge into `count` at `t` (s), counting up; `a_rise`: this edge is
    /// A's rise. Returns the steps it fires or schedules: (time s, ±1).
    pub fn edge(&mut self, t: f64, count: i64, a_rise: bool) -> Vec<(f64, i32)> {
        if a_rise {
            if let Some(r) = self.last_rise.replace(t) {
                self.period = Some(t - r).filter(|p| *p < TIMEOUT_S);
            }
        }
        let mut out = Vec::new();
        // the last level due: the Bresenham's (round half up, `gear.hpp`)
        // without a period; with one, every level crossed before count+1
        let period = self.period.filter(|_| self.predict);
        let last = match period {
            None => (2 * count * self.num + self.den).div_euclid(2 * self.den),
            Some(_) => ((count + 1) * self.num - 1).div_euclid(self.den),
        };
        while self.steps < last {
            self.steps += 1;
            // where the line crosses this step's level, counts past the edge
            let past = (self.steps * self.den) as f64 / self.num as f64 - count as f64;
            let delay = period.map_or(0.0, |p| p / 4.0 * past.max(0.0));
            let at = (t + delay).max(self.last_step + MIN_GAP_S);
            self.last_step = at;
            out.push((at, self.sense));
        }
        out
    }
}
