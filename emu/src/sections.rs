//! Sections of code that hold an interrupt off, timed on both clocks: the
//! log the chip keeps of each kind (`machine::primask` finds the PRIMASK
//! sections, `tickmask` the ones that mask the tick).

#[derive(Default, Clone, Copy, Debug)]
pub struct Section {
    /// CPU cycles, the model's and the bound's
    pub cycles: u64,
    pub bound: u64,
    pub pc: u32,
    /// the return address when it opened: who called the function that
    /// opened it (a lock's user)
    pub caller: u32,
}

/// An open section: when it began (both clocks), where (pc, caller), and
/// whether the tick's interrupt was enabled.
type Open = ((u64, u64), (u32, u32), bool);

/// Sections of one kind: the one open, and the longest so far (of all, and
/// of those begun with the tick's interrupt enabled).
#[derive(Default)]
pub struct SectionLog {
    since: Option<Open>,
    pub longest: Section,
    pub ticking: Section,
    pub sections: u64,
}

impl SectionLog {
    pub fn is_open(&self) -> bool {
        self.since.is_some()
    }

    /// A section begins at `t` (the model's and the bound's cycle), at `pc`,
    /// in a function called from `caller`.
    pub fn open(&mut self, t: (u64, u64), (pc, caller): (u32, u32), tick_on: bool) {
        self.since = Some((t, (pc, caller), tick_on));
    }

    /// The open section (if any) ends at `t`; the longest are the bound's.
    pub fn close(&mut self, t: (u64, u64)) {
        let Some((t0, (pc, caller), ticking)) = self.since.take() else { return };
        let s = Section { cycles: t.0 - t0.0, bound: t.1 - t0.1, pc, caller };
        self.sections += 1;
        if s.bound > self.longest.bound {
            self.longest = s;
        }
        if ticking && s.bound > self.ticking.bound {
            self.ticking = s;
        }
    }
}
