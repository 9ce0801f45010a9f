//! The check of the image's edge times (`edges`): every pair a tick passed
//! its core is A's last rise as TIM3 and TIM5 latched it, every tick after
//! the first rise has one, and the first tick's instant is the stamp the
//! image's start measured.

use crate::chip::tape::Tape;
use crate::edge_times::Capture;

/// What the check found.
#[derive(Debug, Default)]
pub struct EdgeCheck {
    pub ticks: usize,
    /// ticks that passed an edge, and A rises the models latched
    pub timed: usize,
    pub captures: usize,
    /// ticks after the first rise without an edge
    pub missing: usize,
    /// the first tick whose pair is not A's last rise
    pub wrong: Option<String>,
    /// the image's first instant and TIM5 at TIM11's first update
    pub first_instant: Option<u16>,
    pub first_update: Option<u16>,
    /// the count the image found A and B low at, mod 4
    pub low_low: Option<u16>,
}

impl EdgeCheck {
    pub fn ok(&self) -> bool {
        self.timed > 0
            && self.missing == 0
            && self.wrong.is_none()
            && self.first_instant.is_some()
            && self.first_instant == self.first_update
            && self.low_low == Some(0)
    }
}

/// The last capture at or before cycle `t` (a capture and a read in the same
/// cycle: the capture came first, between two runs of the CPU).
fn last_before(captures: &[Capture], t: u64) -> Option<&Capture> {
    captures[..captures.partition_point(|c| c.at <= t)].last()
}

/// Judges `tape`'s ticks; `low_low` is k0 mod 4 from the image's clock (the
/// jobs boot with the lathe at count 0 in state (0, 0): k0 ≡ 0).
pub fn judge(tape: &Tape, low_low: Option<u16>) -> EdgeCheck {
    let mut c = EdgeCheck {
        ticks: tape.ticks.len(),
        captures: tape.captures.len(),
        first_instant: tape.edge_clock.map(|k| k.first_instant),
        first_update: tape.first_update_stamp,
        low_low,
        wrong: tape.edge_read_wrong.clone(),
        ..EdgeCheck::default()
    };
    for (k, t) in tape.ticks.iter().enumerate() {
        let got = t.input.lathe_edge;
        c.timed += got.is_some() as usize;
        let want = last_before(&tape.captures, t.edge_read_at.unwrap_or(t.at)).map(|e| e.regs);
        if got.is_none() && want.is_some() {
            c.missing += 1;
        } else if got != want && c.wrong.is_none() {
            c.wrong = Some(format!("tick {k}: passed {got:?}, A's last rise {want:?}"));
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chip::tape::TickSeen;
    use polyturn_sync::edges::EdgeRegs;
    use polyturn_sync::TickInput;

    fn tick(at: u64, edge: Option<EdgeRegs>) -> TickSeen {
        let input = TickInput { lathe_edge: edge, ..TickInput::default() };
        TickSeen { at, input, enable: false, edge_read_at: edge.map(|_| at + 10) }
    }

    #[test]
    fn a_pair_is_judged_against_the_last_rise_before_its_read() {
        let e = |count, stamp| EdgeRegs { count, stamp };
        let mut tape = Tape::default();
        tape.captures = vec![Capture { at: 100, regs: e(4, 7) }, Capture { at: 205, regs: e(8, 9) }];
        tape.ticks = vec![tick(50, None), tick(150, Some(e(4, 7))), tick(200, Some(e(8, 9)))];
        tape.first_update_stamp = Some(40);
        tape.edge_clock = Some(polyturn_sync::edges::EdgeClock { first_instant: 40, ..Default::default() });
        let c = judge(&tape, Some(0));
        assert!(c.ok(), "{c:?}");
        assert_eq!((c.timed, c.captures), (2, 2));
        tape.ticks.push(tick(300, None));
        assert_eq!(judge(&tape, Some(0)).missing, 1, "a tick after a rise without an edge");
        tape.ticks[3] = tick(300, Some(e(4, 7)));
        assert!(judge(&tape, Some(0)).wrong.is_some());
        tape.ticks.pop();
        assert!(!judge(&tape, Some(1)).ok(), "k0 must be the boot's count 0");
    }
}
