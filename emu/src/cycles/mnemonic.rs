//! Mnemonics: llvm-objdump's UAL spelling `base{s}{cond}{.w|.n|.<dt>}` split
//! into the instruction's class and whether it carries a condition code.
//! The classes are the rows of the Cortex-M4 TRM (ARM DDI 0439D) Table 3-1
//! (instruction set), Table 3-2 (DSP) and Table 7-1 (FPU).

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// data processing: the first register is written, the rest read
    Dp,
    /// data processing that keeps part of its destination (MOVT, BFI, BFC)
    DpKeep,
    /// CMP, CMN, TST, TEQ: every register read, none written
    Compare,
    /// a 32-bit-result multiply
    Mul,
    /// a 64-bit-result multiply: the first two registers written (and read if it accumulates)
    MulLong {
        acc: bool,
    },
    Div {
        signed: bool,
    },
    Load,
    LoadEx,
    Store,
    StoreEx,
    LoadDouble,
    StoreDouble,
    LoadMultiple,
    StoreMultiple,
    Push,
    Pop,
    Branch,
    Call,
    Cbz,
    BranchReg {
        link: bool,
    },
    Table,
    It,
    Mrs,
    Msr,
    Cps,
    Barrier,
    Isb,
    Hint,
    Trap,
    /// FP data processing: its Table 7-1 cycles, and whether the §7.2.3 note's
    /// result-use stall applies (arithmetic and conversions)
    FpData {
        cycles: u8,
        arith: bool,
    },
    /// VMOV (cycles depend on its operands)
    FpMove,
    Vmrs,
    Vmsr,
    FpLoadStore,
    FpMultiple,
    FpPush,
    FpPop,
}

/// Condition codes (ARMv7-M ARM §A7.3, with llvm's `hs`/`lo` spellings).
const CONDS: [&str; 17] =
    ["eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt", "le", "al"];

/// (class, has a condition code) of a mnemonic, or None if unknown.
pub fn classify(mnemonic: &str) -> Option<(Kind, bool)> {
    let stem = mnemonic.split('.').next().unwrap_or(mnemonic);
    if is_it(stem) {
        return Some((Kind::It, false));
    }
    if let Some(k) = kind(stem) {
        return Some((k, false));
    }
    let flag_setting = |s: &str| {
        s.strip_suffix('s').and_then(kind).filter(|k| matches!(k, Kind::Dp | Kind::Mul | Kind::MulLong { .. }))
    };
    if let Some(base) = CONDS.iter().find_map(|c| stem.strip_suffix(c)) {
        if let Some(k) = kind(base).or_else(|| flag_setting(base)) {
            return Some((k, true));
        }
    }
    flag_setting(stem).map(|k| (k, false))
}

/// IT, ITT, ITE, ... ITEEE: one to four instructions.
fn is_it(stem: &str) -> bool {
    stem.strip_prefix("it").is_some_and(|m| m.len() <= 3 && m.chars().all(|c| c == 't' || c == 'e'))
}

/// How many instructions an IT mnemonic makes conditional.
pub fn it_count(stem: &str) -> u8 {
    stem.len() as u8 - 1
}

fn kind(base: &str) -> Option<Kind> {
    integer(base).or_else(|| memory(base)).or_else(|| control(base)).or_else(|| fp(base))
}

fn integer(b: &str) -> Option<Kind> {
    use Kind::*;
    Some(match b {
        "mov" | "mvn" | "add" | "adc" | "sub" | "sbc" | "rsb" | "and" | "orr" | "orn" | "eor" | "bic" | "lsl"
        | "lsr" | "asr" | "ror" | "rrx" | "adr" | "addw" | "subw" | "movw" | "neg" | "ssat" | "usat" | "ssat16"
        | "usat16" | "sxtb" | "sxth" | "uxtb" | "uxth" | "sxtb16" | "uxtb16" | "sxtab" | "sxtah" | "uxtab"
        | "uxtah" | "sxtab16" | "uxtab16" | "ubfx" | "sbfx" | "clz" | "rev" | "rev16" | "revsh" | "rbit" | "sel"
        | "pkhbt" | "pkhtb" => Dp,
        "movt" | "bfi" | "bfc" => DpKeep,
        "cmp" | "cmn" | "tst" | "teq" => Compare,
        "mul" | "mla" | "mls" | "smmul" | "smmulr" | "smmla" | "smmlar" | "smmls" | "smmlsr" | "smlabb" | "smlabt"
        | "smlatb" | "smlatt" | "smlawb" | "smlawt" | "smlad" | "smladx" | "smlsd" | "smlsdx" | "smuad" | "smuadx"
        | "smusd" | "smusdx" | "smulbb" | "smulbt" | "smultb" | "smultt" | "smulwb" | "smulwt" | "usad8" | "usada8" => {
            Mul
        }
        "smull" | "umull" => MulLong { acc: false },
        "smlal" | "umlal" | "umaal" | "smlalbb" | "smlalbt" | "smlaltb" | "smlaltt" | "smlald" | "smlaldx"
        | "smlsld" | "smlsldx" => MulLong { acc: true },
        "sdiv" => Div { signed: true },
        "udiv" => Div { signed: false },
        _ => return parallel(b).then_some(Dp),
    })
}

/// The ARMv7E-M parallel add/subtract family (Table 3-2 "Addition",
/// "Subtraction", "Parallel Addition and Subtraction": all one cycle):
/// a prefix s q sh u uq uh, an operation add8 add16 sub8 sub16 asx sax.
/// QADD, QSUB, QDADD, QDSUB are the non-parallel saturating rows.
fn parallel(b: &str) -> bool {
    if matches!(b, "qadd" | "qsub" | "qdadd" | "qdsub") {
        return true;
    }
    let ops = ["add8", "add16", "sub8", "sub16", "asx", "sax"];
    ["sh", "uq", "uh", "s", "q", "u"].iter().any(|p| b.strip_prefix(p).is_some_and(|o| ops.contains(&o)))
}

fn memory(b: &str) -> Option<Kind> {
    use Kind::*;
    Some(match b {
        "ldr" | "ldrb" | "ldrh" | "ldrsb" | "ldrsh" | "ldrt" | "ldrbt" | "ldrht" | "ldrsbt" | "ldrsht" | "pld"
        | "pli" => Load,
        "ldrex" | "ldrexb" | "ldrexh" => LoadEx,
        "str" | "strb" | "strh" | "strt" | "strbt" | "strht" => Store,
        "strex" | "strexb" | "strexh" => StoreEx,
        "ldrd" => LoadDouble,
        "strd" => StoreDouble,
        "ldm" | "ldmia" | "ldmfd" | "ldmdb" | "ldmea" => LoadMultiple,
        "stm" | "stmia" | "stmea" | "stmdb" | "stmfd" => StoreMultiple,
        "push" => Push,
        "pop" => Pop,
        _ => return None,
    })
}

fn control(b: &str) -> Option<Kind> {
    use Kind::*;
    Some(match b {
        "b" => Branch,
        "bl" => Call,
        "cbz" | "cbnz" => Cbz,
        "bx" => BranchReg { link: false },
        "blx" => BranchReg { link: true },
        "tbb" | "tbh" => Table,
        "mrs" => Mrs,
        "msr" => Msr,
        "cpsid" | "cpsie" => Cps,
        "dmb" | "dsb" => Barrier,
        "isb" => Isb,
        "nop" | "yield" | "sev" | "wfe" | "wfi" | "clrex" => Hint,
        // `trap` is llvm's name for UDF #254
        "svc" | "bkpt" | "udf" | "trap" => Trap,
        _ => return None,
    })
}

/// Table 7-1 (DDI 0439D §7.2.3).
fn fp(b: &str) -> Option<Kind> {
    use Kind::*;
    Some(match b {
        "vadd" | "vsub" | "vmul" | "vnmul" | "vcvt" | "vcvtr" | "vcvtb" | "vcvtt" => FpData { cycles: 1, arith: true },
        "vabs" | "vneg" | "vcmp" | "vcmpe" => FpData { cycles: 1, arith: false },
        "vmla" | "vmls" | "vnmla" | "vnmls" | "vfma" | "vfms" | "vfnma" | "vfnms" => FpData { cycles: 3, arith: true },
        "vdiv" | "vsqrt" => FpData { cycles: 14, arith: true },
        "vmov" => FpMove,
        "vmrs" => Vmrs,
        "vmsr" => Vmsr,
        "vldr" | "vstr" => FpLoadStore,
        "vldm" | "vldmia" | "vldmdb" | "vstm" | "vstmia" | "vstmdb" => FpMultiple,
        "vpush" => FpPush,
        "vpop" => FpPop,
        _ => return None,
    })
}
