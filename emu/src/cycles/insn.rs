//! One instruction of the image as the timing rules need it (`Insn`, `Op`):
//! the listing (`program`) makes them, the rules (`timing`) price them.

use super::operands::bit;

pub const SP: u8 = 13;
pub const LR: u8 = 14;
pub const PC: u8 = 15;

/// One instruction of the image, as the timing rules need it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Insn {
    pub addr: u32,
    /// 2 or 4 bytes
    pub size: u8,
    pub op: Op,
    /// core registers read, bit n = rn (r13 sp, r14 lr, r15 pc)
    pub reads: u16,
    /// core registers written (a branch writes the pc)
    pub writes: u16,
    /// for loads and stores: the registers the address is generated from
    pub addr_regs: u16,
    /// may not take effect: a condition code in the mnemonic, inside an IT
    /// block, or CBZ/CBNZ
    pub conditional: bool,
}

impl Insn {
    pub fn writes_pc(&self) -> bool {
        self.writes & bit(PC) != 0
    }
}

/// A single load or store (TRM DDI 0439D §3.3.2 times them by these classes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// LDR, LDRB, LDRH, LDRSB, LDRSH (immediate, register or literal), PLD
    Load,
    /// LDREX, STREX and their byte/halfword forms: "pipelined exactly as LDR"
    Exclusive,
    /// STR/STRB/STRH with an immediate offset (or none)
    StoreImm,
    /// STR/STRB/STRH with a register offset
    StoreReg,
}

/// The instruction classes of the timing rules (timing.rs cites each).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// data processing: moves, arithmetic, logic, shifts, compares, extends,
    /// bit fields, reverse, saturate, the DSP parallel arithmetic
    Alu,
    /// multiplies, 32- and 64-bit results, the DSP multiplies
    Mul,
    /// SDIV/UDIV: the registers holding the dividend (Rn) and divisor (Rm)
    Div {
        signed: bool,
        dividend: u8,
        divisor: u8,
    },
    /// a single load or store; `literal`: the address a PC-relative load reads
    Single {
        access: Access,
        literal: Option<u32>,
    },
    /// LDRD/STRD
    Double {
        literal: Option<u32>,
    },
    /// LDM/STM/PUSH/POP with `regs` registers in the list (pc included)
    Multiple {
        regs: u8,
    },
    /// IT covering `count` instructions
    It {
        count: u8,
    },
    /// B, B<cond>, CBZ, CBNZ to an immediate target
    Branch {
        target: u32,
    },
    /// BL
    Call {
        target: u32,
    },
    /// BX, BLX (register), and MOV/ADD with the pc as destination
    BranchReg,
    /// TBB, TBH
    Table,
    /// MRS, MSR, CPSID, CPSIE
    System,
    /// DMB, DSB
    Barrier,
    Isb,
    /// NOP, YIELD, SEV, WFI, WFE, CLREX
    Hint,
    /// SVC, BKPT, UDF: raise an exception
    Trap,
    /// FP data processing and register moves: cycles per Table 7-1;
    /// `arith`: the §7.2.3 note's one-cycle result-use stall can apply
    Fp {
        cycles: u8,
        arith: bool,
    },
    /// VLDR, VSTR, VLDM, VSTM, VPUSH, VPOP moving `words` 32-bit words
    FpMem {
        words: u8,
    },
}
