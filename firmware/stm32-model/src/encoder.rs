//! A reference model of the encoder interface of TIM2..TIM5 (RM0383 §13.3.12 "Encoder
//! interface mode"), as TIM3 decodes the lathe encoder, with channel 3 capturing the
//! count at the index's rising edge (§13.3.5 "Input capture mode"). It is fed pin
//! levels, not bus writes: TIM3 is not on the model's bus.
//!
//! The inputs are taken as TI1FP1 = TI1 and TI2FP2 = TI2 (CC1P = CC2P = 0, §13.4.9); the
//! input filter (ICxF, §13.4.7) only delays an edge that lasts longer than it, so it is
//! left out: a test checks the spacing of the edges against the filter itself.
//!
//! §13.3.12 names SMS = 011 for counting on both inputs. For the single-input modes the
//! section ("SMS = 001 if the counter is counting on TI2 edges only, SMS = 010 if it is
//! counting on TI1 edges only") and the SMCR description (§13.4.3: 001 counts on TI1FP1
//! edges, 010 on TI2FP2 edges) disagree, so [`Counting`] names the table's columns,
//! not SMS values.

use crate::unmodelled;

/// Which edges the counter counts: the three groups of rows of §13.3.12 Table 53
/// "Counting direction versus encoder signals".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Counting {
    Ti1Only,
    Ti2Only,
    /// SMS = 011 (§13.4.3 "Encoder mode 3"): both edges of both inputs.
    Both,
}

/// What one transition did to the counter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Count {
    Up,
    Down,
    None,
}

/// Table 53, one row per (counting group, level of the opposite signal), columns: TI1FP1
/// rising, TI1FP1 falling, TI2FP2 rising, TI2FP2 falling. "Opposite signal" is TI2FP2 for
/// an edge on TI1 and TI1FP1 for an edge on TI2.
pub fn table_53(counting: Counting, opposite_high: bool) -> [Count; 4] {
    use Count::{Down as D, None as N, Up as U};
    match (counting, opposite_high) {
        (Counting::Ti1Only, true) => [D, U, N, N],
        (Counting::Ti1Only, false) => [U, D, N, N],
        (Counting::Ti2Only, true) => [N, N, U, D],
        (Counting::Ti2Only, false) => [N, N, D, U],
        (Counting::Both, true) => [D, U, U, D],
        (Counting::Both, false) => [U, D, D, U],
    }
}

/// TIM3 in encoder interface mode with channel 3 capturing on TI3's rising edge.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Encoder {
    counting: Counting,
    arr: u16,
    cnt: u16,
    /// CR1.DIR: 1 = counting down (§13.4.1).
    dir_down: bool,
    ti: [bool; 3],
    /// Signed sum of the counts (a test convenience: CNT without the wrap).
    position: i64,
    ccr3: u16,
    cc3if: bool,
    cc3of: bool,
}

impl Encoder {
    /// Counting enabled (CEN = 1) with CNT = 0, the counter's range `0..=arr`, and the
    /// inputs at their present levels (TI1, TI2, TI3).
    pub fn new(counting: Counting, arr: u16, levels: [bool; 3]) -> Encoder {
        if arr == 0 {
            unmodelled("encoder with ARR = 0: \"the counter is blocked while the auto-reload value is null\"");
        }
        let (cnt, dir_down, position, ccr3, cc3if, cc3of) = (0, false, 0, 0, false, false);
        Encoder { counting, arr, cnt, dir_down, ti: levels, position, ccr3, cc3if, cc3of }
    }

    /// TI1 and TI2 take new levels. A change of one input counts as Table 53 says; "the
    /// DIR bit is calculated at each transition on any input (TI1 or TI2), whatever the
    /// counter is counting on" (§13.3.12), i.e. as the both-inputs rows say. The table
    /// assumes "TI1 and TI2 do not switch at the same time": a change of both panics.
    pub fn input(&mut self, ti1: bool, ti2: bool) -> Count {
        let (c1, c2) = (ti1 != self.ti[0], ti2 != self.ti[1]);
        if c1 && c2 {
            unmodelled("TI1 and TI2 switched at the same time (Table 53 assumes they do not)");
        }
        if !c1 && !c2 {
            return Count::None;
        }
        let (col, opposite) = if c1 { (if ti1 { 0 } else { 1 }, ti2) } else { (if ti2 { 2 } else { 3 }, ti1) };
        self.ti[0] = ti1;
        self.ti[1] = ti2;
        self.dir_down = table_53(Counting::Both, opposite)[col] == Count::Down;
        let count = table_53(self.counting, opposite)[col];
        self.apply(count);
        count
    }

    /// "The counter just counts continuously between 0 and the auto-reload value in the
    /// TIMx_ARR register (0 to ARR or ARR down to 0 depending on the direction)".
    fn apply(&mut self, count: Count) {
        match count {
            Count::Up => {
                self.cnt = if self.cnt >= self.arr { 0 } else { self.cnt + 1 };
                self.position += 1;
            }
            Count::Down => {
                self.cnt = if self.cnt == 0 { self.arr } else { self.cnt - 1 };
                self.position -= 1;
            }
            Count::None => {}
        }
    }

    /// TI3 takes a new level. A rising edge captures CNT into CCR3 and sets CC3IF, or
    /// CC3OF if CC3IF was still set (§13.3.5: "When an input capture occurs: The TIMx_CCR1
    /// register gets the value of the counter on the active transition. CC1IF flag is set
    /// ... CC1OF is also set if at least two consecutive captures occurred whereas the
    /// flag was not cleared").
    pub fn index(&mut self, ti3: bool) {
        if ti3 && !self.ti[2] {
            self.ccr3 = self.cnt;
            self.cc3of |= self.cc3if;
            self.cc3if = true;
        }
        self.ti[2] = ti3;
    }

    /// The capture as the firmware takes it: CCR3 if CC3IF is set; reading CCR3 clears
    /// CC3IF (§13.4.5 "cleared by software reading the TIMx_CCR1 register").
    pub fn take_capture(&mut self) -> Option<u16> {
        std::mem::take(&mut self.cc3if).then_some(self.ccr3)
    }

    pub fn cnt(&self) -> u16 {
        self.cnt
    }
    /// CR1.DIR: true when the last transition was a downward one.
    pub fn dir_down(&self) -> bool {
        self.dir_down
    }
    pub fn position(&self) -> i64 {
        self.position
    }
    /// CC3OF: a capture was overwritten before it was read.
    pub fn overcaptured(&self) -> bool {
        self.cc3of
    }
}
