//! An instruction's registers and class from its mnemonic's class and its
//! operand text: which registers it reads, writes and forms an address from.

use super::insn::{Access, Insn, Op, LR, PC, SP};
use super::mnemonic::{it_count, Kind};
use super::operands::{address, bit, is_fp_reg, list, mem, reg, regs_in, split_top, Mem};

/// The instruction from its class and operands (size and IT state set by the caller).
pub fn build(addr: u32, kind: Kind, mnemonic: &str, ops_text: &str, comment: &str) -> Result<Insn, String> {
    let ops_text = ops_text.split('<').next().unwrap_or(ops_text).trim(); // drop `<symbol+off>`
    let ops = split_top(ops_text);
    let mut i = Insn { addr, size: 0, op: Op::Alu, reads: 0, writes: 0, addr_regs: 0, conditional: false };
    match kind {
        Kind::Dp | Kind::DpKeep | Kind::Compare | Kind::Mul | Kind::MulLong { .. } | Kind::Div { .. } => {
            data_processing(&mut i, kind, mnemonic, &ops)?
        }
        Kind::Load | Kind::LoadEx | Kind::Store | Kind::StoreEx | Kind::LoadDouble | Kind::StoreDouble => {
            single(&mut i, kind, &ops, comment)?
        }
        Kind::LoadMultiple | Kind::StoreMultiple | Kind::Push | Kind::Pop => multiple(&mut i, kind, &ops)?,
        Kind::FpData { .. } | Kind::FpMove | Kind::Vmrs | Kind::Vmsr => fp_data(&mut i, kind, &ops),
        Kind::FpLoadStore | Kind::FpMultiple | Kind::FpPush | Kind::FpPop => fp_memory(&mut i, kind, &ops)?,
        _ => control(&mut i, kind, mnemonic, &ops)?,
    }
    Ok(i)
}

fn regs_of(ops: &[&str]) -> u16 {
    ops.iter().fold(0, |m, o| m | regs_in(o))
}

/// Data processing whose second operand is its only source.
const UNARY: [&str; 10] = ["mov", "mvn", "neg", "clz", "rev", "rbit", "sxt", "uxt", "rrx", "adr"];

fn data_processing(i: &mut Insn, kind: Kind, mnemonic: &str, ops: &[&str]) -> Result<(), String> {
    let dest = || ops.first().and_then(|o| reg(o)).ok_or("no destination register");
    i.op = Op::Alu;
    match kind {
        Kind::Compare => i.reads = regs_of(ops),
        Kind::MulLong { acc } => {
            let (lo, hi) = (dest()?, ops.get(1).and_then(|o| reg(o)).ok_or("no second destination")?);
            i.writes = bit(lo) | bit(hi);
            i.reads = regs_of(&ops[2..]) | if acc { i.writes } else { 0 };
            i.op = Op::Mul;
        }
        Kind::Div { signed } => {
            let r = |k: usize| ops.get(k).and_then(|o| reg(o)).ok_or("divide needs three registers");
            let (d, n, m) = (dest()?, r(1)?, r(2)?);
            i.writes = bit(d);
            i.reads = bit(n) | bit(m);
            i.op = Op::Div { signed, dividend: n, divisor: m };
        }
        _ => {
            let d = dest()?;
            i.writes = bit(d);
            // the two-operand forms `ands r0, r1`, `adds r0, #1` read their destination too
            let keeps = kind == Kind::DpKeep || ops.len() == 2 && !UNARY.iter().any(|u| mnemonic.starts_with(u));
            i.reads = regs_of(&ops[1..]) | if keeps { bit(d) } else { 0 };
            if kind == Kind::Mul {
                i.op = Op::Mul;
            } else if d == PC {
                i.op = Op::BranchReg; // MOV PC / ADD PC: Table 3-1 "1 + P"
            }
        }
    }
    Ok(())
}

/// The address a PC-relative access reads: Align(PC, 4) + imm, where the
/// PC reads as the instruction's address + 4 (ARMv7-M ARM §A5.1.2).
fn literal(addr: u32, m: &Mem, comment: &str) -> Result<Option<u32>, String> {
    if m.base != Some(PC) {
        return Ok(None);
    }
    let at = ((addr + 4) & !3).wrapping_add(m.imm.unwrap_or(0) as u32);
    match address(comment) {
        Some(shown) if shown != at => Err(format!("literal at {at:#x}, objdump says {shown:#x}")),
        _ => Ok(Some(at)),
    }
}

fn single(i: &mut Insn, kind: Kind, ops: &[&str], comment: &str) -> Result<(), String> {
    let m = mem(ops).ok_or("no memory operand")?;
    let data = regs_of(&ops[..ops.iter().position(|o| o.starts_with('[')).unwrap_or(0)]);
    let wb = if m.writeback { m.base.map_or(0, bit) } else { 0 };
    i.addr_regs = m.addr_regs;
    i.reads = m.addr_regs | m.post_regs;
    let lit = literal(i.addr, &m, comment)?;
    let access = match kind {
        Kind::Load | Kind::LoadEx | Kind::LoadDouble => {
            i.writes = data | wb;
            match kind {
                Kind::LoadEx => Access::Exclusive,
                _ => Access::Load,
            }
        }
        Kind::StoreEx => {
            // STREX Rd, Rt, [Rn]: Rd gets the status
            let status = ops.first().and_then(|o| reg(o)).ok_or("no status register")?;
            i.writes = bit(status) | wb;
            i.reads |= data & !bit(status);
            Access::Exclusive
        }
        _ => {
            i.writes = wb;
            i.reads |= data;
            if m.index.is_some() {
                Access::StoreReg
            } else {
                Access::StoreImm
            }
        }
    };
    i.op = match kind {
        Kind::LoadDouble | Kind::StoreDouble => Op::Double { literal: lit },
        _ => Op::Single { access, literal: lit },
    };
    Ok(())
}

fn multiple(i: &mut Insn, kind: Kind, ops: &[&str]) -> Result<(), String> {
    let (base, wb, regs) = match kind {
        Kind::Push | Kind::Pop => (SP, true, ops.first()),
        _ => {
            let b = ops.first().ok_or("no base register")?;
            (reg(b.trim_end_matches('!')).ok_or("no base register")?, b.ends_with('!'), ops.get(1))
        }
    };
    let l = list(regs.ok_or("no register list")?).ok_or("unreadable register list")?;
    i.addr_regs = bit(base);
    i.reads = bit(base);
    i.writes = if wb { bit(base) } else { 0 };
    match kind {
        Kind::LoadMultiple | Kind::Pop => i.writes |= l.core,
        _ => i.reads |= l.core,
    }
    i.op = Op::Multiple { regs: l.count };
    Ok(())
}

/// FP data processing and transfers to and from core registers (FP registers
/// are not tracked: the masks hold core registers only).
fn fp_data(i: &mut Insn, kind: Kind, ops: &[&str]) {
    let core = regs_of(ops);
    let core_first = ops.first().is_some_and(|o| reg(o).is_some());
    i.op = match kind {
        Kind::FpData { cycles, arith } => Op::Fp { cycles, arith },
        // Table 7-1: VMOV between FP registers or of an immediate, or of one
        // half of a double (a scalar `d0[1]`): 1; of one float or two
        // registers to or from core registers: 2
        Kind::FpMove if core != 0 && !ops.iter().any(|o| o.contains('[')) => Op::Fp { cycles: 2, arith: false },
        _ => Op::Fp { cycles: 1, arith: false },
    };
    if core_first || kind == Kind::Vmrs {
        i.writes = core;
    } else {
        i.reads = core;
    }
}

fn fp_memory(i: &mut Insn, kind: Kind, ops: &[&str]) -> Result<(), String> {
    let words = match kind {
        Kind::FpLoadStore => {
            let r = ops.first().ok_or("no FP register")?;
            if !is_fp_reg(r) {
                return Err("not an FP register".into());
            }
            if r.starts_with('d') {
                2
            } else {
                1
            }
        }
        _ => list(ops.last().ok_or("no register list")?).ok_or("unreadable register list")?.fp_words,
    };
    let (base, wb) = match kind {
        Kind::FpLoadStore => {
            let m = mem(ops).ok_or("no memory operand")?;
            (m.base.ok_or("no base register")?, false)
        }
        Kind::FpMultiple => {
            let b = ops.first().ok_or("no base register")?;
            (reg(b.trim_end_matches('!')).ok_or("no base register")?, b.ends_with('!'))
        }
        _ => (SP, true),
    };
    i.addr_regs = bit(base);
    i.reads = bit(base);
    i.writes = if wb { bit(base) } else { 0 };
    i.op = Op::FpMem { words };
    Ok(())
}

fn control(i: &mut Insn, kind: Kind, mnemonic: &str, ops: &[&str]) -> Result<(), String> {
    let target = || ops.last().and_then(|o| address(o)).ok_or("no branch target");
    i.op = match kind {
        Kind::It => Op::It { count: it_count(mnemonic.split('.').next().unwrap_or(mnemonic)) },
        Kind::Branch => Op::Branch { target: target()? },
        Kind::Cbz => {
            i.reads = regs_in(ops.first().ok_or("no register")?);
            i.conditional = true;
            Op::Branch { target: target()? }
        }
        Kind::Call => {
            i.writes = bit(LR);
            Op::Call { target: target()? }
        }
        Kind::BranchReg { link } => {
            i.reads = regs_of(ops);
            i.writes = if link { bit(LR) } else { 0 };
            Op::BranchReg
        }
        Kind::Table => {
            let m = mem(ops).ok_or("no memory operand")?;
            (i.addr_regs, i.reads) = (m.addr_regs, m.addr_regs);
            Op::Table
        }
        Kind::Mrs => {
            i.writes = regs_of(ops);
            Op::System
        }
        Kind::Msr => {
            i.reads = regs_of(ops);
            Op::System
        }
        Kind::Cps => Op::System,
        Kind::Barrier => Op::Barrier,
        Kind::Isb => Op::Isb,
        Kind::Hint => Op::Hint,
        Kind::Trap => Op::Trap,
        _ => return Err(format!("no operand rule for {kind:?}")),
    };
    if matches!(i.op, Op::Branch { .. } | Op::Call { .. } | Op::BranchReg | Op::Table) {
        i.writes |= bit(PC);
    }
    Ok(())
}
