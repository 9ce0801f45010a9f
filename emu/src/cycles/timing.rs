//! Cycles the Cortex-M4 core spends per instruction at zero wait states, from
//! the Cortex-M4 Technical Reference Manual r0p1, ARM DDI 0439D ("the TRM"):
//! §3.3.1 Table 3-1 (instruction set) and Table 3-2 (DSP), §3.3.2 (load/store
//! timings), §7.2.3 Table 7-1 (FPU).
//!
//! Two figures: `model`, what silicon most likely spends, and `bound`, what it
//! cannot exceed (every unknown at its worst). Wait states, bus contention,
//! exceptions and the write buffer's drain are the caller's; so is the
//! pipeline refill after a taken branch (`refill`), since only the caller
//! sees whether the next block is the fall-through.

use super::insn::{Access, Insn, Op, PC};
use std::ops::{Add, AddAssign};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cost {
    pub model: u32,
    pub bound: u32,
}

impl Add for Cost {
    type Output = Cost;
    fn add(self, o: Cost) -> Cost {
        Cost { model: self.model + o.model, bound: self.bound + o.bound }
    }
}

impl AddAssign for Cost {
    fn add_assign(&mut self, o: Cost) {
        *self = *self + o;
    }
}

const fn c(model: u32, bound: u32) -> Cost {
    Cost { model, bound }
}

/// P, Table 3-1's key: "the number of cycles required for a pipeline refill.
/// This ranges from 1 to 3 depending on the alignment and width of the target
/// instruction, and whether the processor manages to speculate the address
/// early". The top of that range covers alignment and width: the bound.
pub const REFILL_MAX: u32 = 3;

/// What `block_cost` counts for an SDIV/UDIV: Table 3-1 "2 to 12" (note a:
/// "dependent on the values of the input operands"), the model at the
/// minimum until the caller adds `divide(..).model - DIVIDE_IN_BLOCK.model`.
pub const DIVIDE_IN_BLOCK: Cost = c(2, 12);

/// One instruction's own cycles, its neighbours and any refill aside.
fn issue(i: &Insn) -> Cost {
    match i.op {
        // Table 3-1: MOV..RRX, CLZ, extend, bit field, reverse rows: 1; Table
        // 3-2: every DSP row (multiplies included) 1. Multiplies: Table 3-1
        // MUL, MLA, MLS, SMULL, UMULL, SMLAL, UMLAL: 1.
        Op::Alu | Op::Mul => c(1, 1),
        Op::Div { .. } => DIVIDE_IN_BLOCK,
        // Table 3-1 IT: 1 (note d's folding is a neighbour rule).
        Op::It { .. } => c(1, 1),
        Op::Single { access, .. } => single(i, access),
        // Table 3-1 LDRD/STRD "1 + N", N = 2; §3.3.2: "this operation requires
        // three cycles when not stalled".
        Op::Double { .. } => c(3, 3) + literal_fetch(i),
        // Table 3-1 LDM/STM/PUSH/POP "1 + N" (N counts PC and LR); with PC,
        // "+ P" is the refill. §3.3.2 agrees ("an eight element store takes
        // nine cycles").
        Op::Multiple { regs } => c(1 + regs as u32, 1 + regs as u32),
        // Table 3-1 B, BL, BX, BLX, CBZ, MOV PC, ADD PC: "1" when not taken
        // (note c), "1 + P" taken: P is `refill`.
        Op::Branch { .. } | Op::Call { .. } | Op::BranchReg => c(1, 1),
        // §3.3.2: "TBB and TBH ... at least two cycles for the load, one cycle
        // for the add, and three cycles for the pipeline reload": 3 here, 3 in
        // `refill`. (Table 3-1 says "2 + P"; §3.3.2 is the more specific.)
        Op::Table => c(3, 3) + literal_fetch(i),
        // Table 3-1 CPSID, CPSIE, MRS, MSR: "1 or 2", with no word on which
        // case is 1: both figures take 2.
        Op::System => c(2, 2),
        // Table 3-1 DMB, DSB "1 + B", B's minimum 0; the write buffer's drain
        // (§3.5: "DMB and DSB instructions wait for the write buffer to drain")
        // is the caller's.
        Op::Barrier => c(1, 1),
        // Table 3-1 ISB "1 + B", and for ISB "the minimum number of cycles is
        // equivalent to the number required for a pipeline refill": a refill
        // of the next instruction, sequential like an immediate branch's.
        Op::Isb => c(2, 1 + REFILL_MAX),
        // Table 3-1 NOP, SEV: 1; WFE, WFI "1 + W" (W, the wait, is the
        // caller's); CLREX 1. SVC, BKPT (and UDF) have no cycles in the
        // table: their issue counts 1 and the exception entry is the caller's.
        Op::Hint | Op::Trap => c(1, 1),
        // Table 7-1; the §7.2.3 note: arithmetic and conversions "take one
        // cycle longer if their result is consumed by the following
        // instruction". FP registers are not tracked, so the bound takes it
        // and the model does not.
        Op::Fp { cycles, arith } => c(cycles as u32, cycles as u32 + arith as u32),
        // Table 7-1: VLDR/VSTR.32 2, .64 3; VLDM/VSTM/VPUSH/VPOP .32 "1+N",
        // .64 "1+2*N": one cycle plus one per 32-bit word.
        Op::FpMem { words } => c(1 + words as u32, 1 + words as u32) + literal_fetch(i),
    }
}

/// Table 3-1: every single load and store "2". §3.3.2: "STR Rx,[Ry,#imm] is
/// always one cycle ... the data store is performed at the same time as the
/// next instruction is executing. If the store is to the write buffer, and the
/// write buffer is full or not enabled, the next instruction is delayed": the
/// bound keeps Table 3-1's 2. A store with a register offset: 2.
fn single(i: &Insn, access: Access) -> Cost {
    match access {
        Access::StoreImm => c(1, 2),
        Access::Load | Access::Exclusive | Access::StoreReg => c(2, 2) + literal_fetch(i),
    }
}

/// §3.3.2: "LDR Rx,[PC,#imm] might add a cycle because of contention with the
/// fetch unit": the bound takes it for every read at a PC-relative address.
fn literal_fetch(i: &Insn) -> Cost {
    c(0, (i.addr_regs & 1 << PC != 0) as u32)
}

fn is_memory(op: Op) -> bool {
    matches!(op, Op::Single { .. } | Op::Double { .. } | Op::Multiple { .. } | Op::Table | Op::FpMem { .. })
}

/// The instructions whose result the register bank receives from the execute
/// stage: §3.3.2's "data processing operation" (multiplies, divides, MRS and
/// FP-to-core moves write the same way).
fn computes(op: Op) -> bool {
    matches!(op, Op::Alu | Op::Mul | Op::Div { .. } | Op::System | Op::Fp { .. })
}

/// §3.3.2: "LDR [any] are pipelined when possible. This means that if the next
/// instruction is an LDR or STR, and the destination of the first LDR is not
/// used to compute the address for the next instruction, then one cycle is
/// removed from the cost of the next instruction"; "LDREX and STREX can be
/// pipelined exactly as LDR"; "nothing can be pipelined after the store"; LDRD,
/// STRD, LDM, STM "cannot be pipelined with preceding or following
/// instructions". A load to the PC is followed by its target, not pipelined.
fn pipelined(prev: &Insn, cur: &Insn) -> bool {
    let loads = matches!(prev.op, Op::Single { access: Access::Load | Access::Exclusive, .. }) && !prev.writes_pc();
    let single = matches!(cur.op, Op::Single { .. });
    loads && single && cur.addr_regs & prev.writes == 0
}

/// The pairing rules between an instruction and the one before it (None:
/// unknown, e.g. the first of a block whose predecessor the caller did not give).
fn pairing(prev: Option<&Insn>, cur: &Insn) -> (u32, Cost) {
    let mut credit = 0; // taken off the model only
    let mut extra = Cost::default();
    match prev {
        Some(p) => {
            // §3.3.2: "Any load or store that generates an address dependent
            // on the result of a preceding data processing operation stalls
            // the pipeline for an additional cycle while the register bank is
            // updated. There is no forwarding path for this scenario."
            if is_memory(cur.op) && computes(p.op) && cur.addr_regs & p.writes & !(1 << PC) != 0 {
                extra += c(1, 1);
            }
            // Pipelining: 2 becomes 1 (a STR with an immediate is 1 already).
            // Table 3-1 note b: "in some cases such as 32-bit opcodes aligned
            // on odd halfword boundaries they might not pipeline optimally":
            // no credit in the bound.
            if pipelined(p, cur) && issue(cur).model > 1 {
                credit += 1;
            }
            // Table 3-1 note d: "An IT instruction can be folded onto a
            // preceding 16-bit Thumb instruction, enabling execution in zero
            // cycles." The bound does not count on it. (A PC-writer before it
            // means the IT was fetched as a branch target, not behind it.)
            if matches!(cur.op, Op::It { .. }) && p.size == 2 && !p.writes_pc() {
                credit += 1;
            }
        }
        // Unknown predecessor: the bound assumes it computed the address.
        None if is_memory(cur.op) && cur.addr_regs & !(1 << PC) != 0 => extra += c(0, 1),
        None => {}
    }
    (credit, extra)
}

/// The block's cost in CPU cycles at zero wait states, the refill of a taken
/// branch at its end excluded (the caller adds `refill` when the next block is
/// not the fall-through). Pairing rules apply between neighbours inside the
/// block; the first instruction's predecessor is unknown (see `block_cost_after`).
pub fn block_cost(insns: &[Insn]) -> Cost {
    block_cost_after(None, insns)
}

/// `block_cost` given the instruction that ran just before the block (the last
/// of the previous block), so the pairing rules apply across the boundary.
pub fn block_cost_after(prev: Option<&Insn>, insns: &[Insn]) -> Cost {
    let mut total = Cost::default();
    let mut before = prev;
    for i in insns {
        let own = issue(i);
        let (credit, extra) = pairing(before, i);
        total += Cost { model: own.model.saturating_sub(credit), bound: own.bound } + extra;
        before = Some(i);
    }
    total
}

/// The refill a taken branch (or any write to the PC) at the end of a block
/// costs over its not-taken cost; `target` is where it went and `target_size`
/// the size of the instruction there.
///
/// Model: P = 1 for an immediate target (B, B<cond>, CBZ, CBNZ, BL) and 2 for
/// a register target (BX, BLX, MOV/ADD PC): the Cortex-M3 TRM's instruction
/// timing notes ("taken branches with an immediate are normally 1 cycle of
/// pipeline reload", "with register operand normally 2"); the M4 TRM gives
/// only the 1-to-3 range. Plus one when the target is a 32-bit instruction
/// that straddles two fetch words (at an address 2 mod 4): P's "alignment and
/// width of the target instruction". Loads to the PC and table branches: 3,
/// §3.3.2 ("LDR PC,[any] ... three cycles for the pipeline reload"; TBB, TBH
/// likewise); LDM/POP with the PC is taken to load the PC the same way.
/// Bound: `REFILL_MAX` for all.
///
/// The model adds one cycle to the immediate and register figures: run on
/// this emulator, CoreMark built with GCC -Os comes out 15 % faster than the
/// one published measurement on this board (a Black Pill F411CE at 96 MHz,
/// 3 wait states: 1.79 CoreMark/MHz), and one more cycle of refill on every
/// taken branch, the rule the figure moves most with, brings it to within
/// 4 % (docs/src/emulator.md, "The cycle clock against CoreMark"). The M4's
/// branch-target speculation through the flash accelerator is the likely
/// reason; the bound is untouched.
pub fn refill(last: &Insn, target: u32, target_size: u8) -> Cost {
    let straddles = (target_size == 4 && target % 4 == 2) as u32;
    let p = match last.op {
        Op::Branch { .. } | Op::Call { .. } => 2 + straddles,
        Op::BranchReg => 3 + straddles,
        Op::Table => 3,
        Op::Single { .. } | Op::Multiple { .. } if last.writes_pc() => 3,
        _ => return Cost::default(),
    };
    c(p.min(REFILL_MAX), REFILL_MAX)
}

/// SDIV/UDIV's whole cost from its operands. Table 3-1: "2 to 12"; note a:
/// "the number of cycles required dependent on the values of the input
/// operands". The M4 TRM gives no formula, so the model is an ESTIMATE: 2 when
/// the quotient is 0 or the divisor is 0; else 2 plus the quotient's width in
/// bits (clz(divisor) - clz(dividend) + 1, the form the Cortex-R4 TRM DDI 0363G
/// §C.8 states for its divider) scaled so a 32-bit quotient takes 12. Signed
/// operands by magnitude. The bound is the table's 12.
pub fn divide(dividend: u32, divisor: u32, signed: bool) -> Cost {
    let (n, d) =
        if signed { ((dividend as i32).unsigned_abs(), (divisor as i32).unsigned_abs()) } else { (dividend, divisor) };
    if d == 0 || d > n {
        return c(2, 12);
    }
    let bits = d.leading_zeros() - n.leading_zeros() + 1; // 1..=32
    c(2 + (10 * bits).div_ceil(32), 12)
}

/// §3.3.2: "A byte aligned halfword load or store adds one extra cycle ... A
/// halfword aligned word load or store adds one extra cycle ... A byte-aligned
/// word load or store adds two extra cycles"; "A STR or STRH cannot delay the
/// processor because of the write buffer": the model spares stores, the bound
/// does not. `bytes` is the access's size (1, 2 or 4). Not charged by the
/// meter yet: it does not see data addresses (docs/src/emulator.md, "What is
/// not modelled").
#[cfg_attr(not(test), allow(dead_code))]
pub fn unaligned(addr: u32, bytes: u32, store: bool) -> Cost {
    let extra = match bytes {
        2 => addr & 1,
        4 if addr & 1 != 0 => 2,
        4 => (addr & 2) >> 1,
        _ => 0,
    };
    c(if store { 0 } else { extra }, extra)
}
