//! The lathe's edge times as the image's tick read them (`edgetime`): the
//! emulated TIM3 latches the count at A's rise and pulses TRGO, which reaches
//! TIM5's channel 3 through ITR1 (`chip::gptimer::trigger`), so the tick reads
//! real edge registers while the lathe turns. The tape keeps every capture
//! the models made and each tick's reads of the registers; the pair a tick
//! passed to its core is rebuilt from those reads by the firmware's own read
//! (`edgetime::read::lathe`), and judged against the captures.

use polyturn_firmware::edgetime::{off, read, TIM3, TIM5};
use polyturn_firmware::regs::Bus;
use polyturn_sync::edges::EdgeRegs;

/// An A rise TIM3 captured: the cycle, TIM3_CCR1 and TIM5's count then.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capture {
    pub at: u64,
    pub regs: EdgeRegs,
}

/// Whether a read of `word` is one of the tick's edge-time reads.
pub fn is_edge_read(word: u32) -> bool {
    [TIM5 + off::CCR3, TIM3 + off::CCR1, TIM3 + off::CNT].contains(&word)
}

/// One tick's reads of `is_edge_read`'s registers, in order, played back
/// to the firmware's read: what it made of them, or why the reads are not
/// the ones it makes.
pub fn pair(reads: &[(u32, u32)]) -> Result<Option<EdgeRegs>, String> {
    if !reads.iter().any(|r| r.0 != TIM3 + off::CNT) {
        return Ok(None); // the gate was shut: the count alone
    }
    let mut bus = Playback { reads, next: 0, wrong: None };
    let (_, edge) = read::lathe(read::Gate::Open, &mut bus);
    match bus.wrong {
        Some(w) => Err(w),
        None if bus.next != reads.len() => Err(format!("{} reads, the read makes {}", reads.len(), bus.next)),
        None => Ok(edge),
    }
}

struct Playback<'a> {
    reads: &'a [(u32, u32)],
    next: usize,
    wrong: Option<String>,
}

impl Bus for Playback<'_> {
    fn write(&mut self, addr: u32, _: u32) {
        self.wrong = Some(format!("the read wrote {addr:#010x}"));
    }
    fn read(&mut self, addr: u32) -> u32 {
        let got = self.reads.get(self.next).copied();
        self.next += 1;
        match got {
            Some((a, v)) if a == addr => v,
            _ => {
                self.wrong.get_or_insert(format!("read {} was {got:x?}, the read makes {addr:#010x}", self.next));
                0
            }
        }
    }
    fn delay(&mut self, _: u32) {}
}
