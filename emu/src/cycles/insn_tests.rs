//! The parser on small llvm-objdump snippets (the layout `llvm-objdump -d`
//! prints: address, raw halfwords, tab, mnemonic, tab, operands, comment).

use super::insn::{Access, Op};
use super::program::Program;

/// r0 = bit 0 ... pc = bit 15
fn regs(rs: &[u8]) -> u16 {
    rs.iter().fold(0, |m, r| m | 1 << r)
}

fn one(line: &str) -> super::insn::Insn {
    let p = Program::parse(line);
    assert!(p.unknown().is_empty(), "{:?}", p.unknown());
    assert_eq!(p.insns().len(), 1, "{line}");
    p.insns()[0]
}

const SNIPPET: &str = "
08000198 <__stext>:
 8000198: f012 fd03    \tbl\t0x8012ba2 <__pre_init>  @ imm = #0x12a06
 800019c: 480e         \tldr\tr0, [pc, #0x38]         @ 0x80001d8 <__stext+0x40>
 80001a4: d001         \tbeq\t0x80001aa <__stext+0x12> @ imm = #0x2
 80001a6: c004         \tstm\tr0!, {r2}
 80001a8: e7fb         \tb\t0x80001a2 <__stext+0xa> @ imm = #-0xa
 80001aa: f8d1 0004    \tldr.w\tr0, [r1, #4]
 80001ae: bf00         \tnop
 80001b0: b8 08 00 20  \t.word\t0x200008b8
 80001b4: 28 00        \t.short\t0x0028
 80001b6: 4770         \tbx\tlr
";

#[test]
fn sizes_come_from_the_raw_halfwords_and_data_is_skipped() {
    let p = Program::parse(SNIPPET);
    assert!(p.unknown().is_empty(), "{:?}", p.unknown());
    let sizes: Vec<(u32, u8)> = p.insns().iter().map(|i| (i.addr, i.size)).collect();
    assert_eq!(
        sizes,
        [
            (0x8000198, 4),
            (0x800019c, 2),
            (0x80001a4, 2),
            (0x80001a6, 2),
            (0x80001a8, 2),
            (0x80001aa, 4),
            (0x80001ae, 2),
            (0x80001b6, 2)
        ],
        "the .word and .short at 80001b0/80001b4 are data"
    );
}

#[test]
fn block_and_at_map_the_boot_alias_to_flash() {
    let p = Program::parse(SNIPPET);
    let b = p.block(0x1a4, 8); // the alias at 0 of 0x80001a4..0x80001ac
    assert_eq!(b.iter().map(|i| i.addr).collect::<Vec<_>>(), [0x80001a4, 0x80001a6, 0x80001a8, 0x80001aa]);
    assert_eq!(p.at(0x19c).map(|i| i.addr), Some(0x800019c));
    assert_eq!(p.at(0x800019e), None, "not an instruction's first byte");
    assert!(p.block(0x80001b0, 6).is_empty(), "data only");
}

#[test]
fn branch_targets_and_the_literal_address_are_recorded() {
    let p = Program::parse(SNIPPET);
    let op = |a| p.at(a).unwrap().op;
    assert_eq!(op(0x8000198), Op::Call { target: 0x8012ba2 });
    assert_eq!(op(0x800019c), Op::Single { access: Access::Load, literal: Some(0x80001d8) });
    assert_eq!(op(0x80001a4), Op::Branch { target: 0x80001aa });
    assert!(p.at(0x80001a4).unwrap().conditional, "beq");
    assert!(!p.at(0x80001a8).unwrap().conditional, "b");
    let cbz = one(" 80001a4: b118         \tcbz\tr0, 0x80001ba <x+0x12> @ imm = #0x6");
    assert_eq!((cbz.op, cbz.reads, cbz.conditional), (Op::Branch { target: 0x80001ba }, regs(&[0]), true));
    let wide = one(" 8000300: f8df 1010    \tldr.w\tr1, [pc, #-0x10]     @ 0x80002f4 <x>");
    assert_eq!(wide.op, Op::Single { access: Access::Load, literal: Some(0x80002f4) }, "Align(pc,4) - 16");
}

#[test]
fn a_literal_address_that_disagrees_with_objdump_is_reported() {
    let p = Program::parse(" 800019c: 480e         \tldr\tr0, [pc, #0x38]         @ 0x80001dc <x>");
    assert_eq!(p.unknown().len(), 1, "computed 0x80001d8");
}

#[test]
fn an_it_block_makes_exactly_its_instructions_conditional() {
    let p = Program::parse(
        " 8000100: bf1e         \tittt\tne
 8000102: 2001         \tmovne\tr0, #0x1
 8000104: 6808         \tldrne\tr0, [r1]
 8000106: f04f 0101    \tmovne.w\tr1, #0x1
 8000108: 2200         \tmovs\tr2, #0x0
 800010a: bf0c         \tite\teq
 800010c: 2001         \tmoveq\tr0, #0x1
 800010e: 2000         \tmovne\tr0, #0x0
 8000110: 4770         \tbx\tlr",
    );
    assert!(p.unknown().is_empty(), "{:?}", p.unknown());
    let cond: Vec<bool> = p.insns().iter().map(|i| i.conditional).collect();
    assert_eq!(cond, [false, true, true, true, false, false, true, true, false]);
    assert_eq!(p.insns()[0].op, Op::It { count: 3 });
    assert_eq!(p.insns()[5].op, Op::It { count: 2 });
}

#[test]
fn register_lists_ranges_and_aliases() {
    let push = one(" 8000208: b5d0         \tpush\t{r4, r6, r7, lr}");
    assert_eq!((push.op, push.reads, push.writes), (Op::Multiple { regs: 4 }, regs(&[4, 6, 7, 14, 13]), regs(&[13])));
    let pop = one(" 8000246: e8bd 8ff0    \tpop.w\t{r4-r11, pc}");
    assert_eq!(pop.op, Op::Multiple { regs: 9 });
    assert_eq!(pop.writes, regs(&[4, 5, 6, 7, 8, 9, 10, 11, 15, 13]));
    assert!(pop.writes_pc());
    let ldm = one(" 8000300: e89e 0007    \tldm.w\tlr, {r0, r1, r2}");
    assert_eq!((ldm.addr_regs, ldm.writes), (regs(&[14]), regs(&[0, 1, 2])), "no writeback without !");
    let alias = one(" 8000300: 4660         \tmov\tr0, ip");
    assert_eq!(alias.reads, regs(&[12]));
    let alias = one(" 8000300: 46d9         \tmov\tsb, fp");
    assert_eq!((alias.writes, alias.reads), (regs(&[9]), regs(&[11])));
    let sl = one(" 8000300: f8da 0000    \tldr.w\tr0, [sl]");
    assert_eq!(sl.addr_regs, regs(&[10]));
}

#[test]
fn loads_and_stores_name_their_address_registers() {
    let ld = one(" 8000300: f850 1022    \tldr.w\tr1, [r0, r2, lsl #2]");
    assert_eq!((ld.addr_regs, ld.writes), (regs(&[0, 2]), regs(&[1])));
    let post = one(" 8000300: e8f4 0102    \tldrd\tr0, r1, [r4], #8");
    assert_eq!((post.op, post.writes), (Op::Double { literal: None }, regs(&[0, 1, 4])), "post-index writes back");
    let pre = one(" 8002a04: f84d 8d04    \tstr\tr8, [sp, #-4]!");
    assert_eq!(pre.op, Op::Single { access: Access::StoreImm, literal: None });
    assert_eq!((pre.reads, pre.writes), (regs(&[8, 13]), regs(&[13])));
    let reg = one(" 8000300: 5088         \tstr\tr0, [r1, r2]");
    assert_eq!(reg.op, Op::Single { access: Access::StoreReg, literal: None });
    let strex = one(" 8000300: e841 2300    \tstrex\tr3, r2, [r1]");
    assert_eq!(strex.op, Op::Single { access: Access::Exclusive, literal: None });
    assert_eq!((strex.writes, strex.reads), (regs(&[3]), regs(&[1, 2])));
    let ldpc = one(" 8000300: f85d fb04    \tldr\tpc, [sp], #4");
    assert!(ldpc.writes_pc());
}

#[test]
fn control_flow_and_system_classes() {
    let cases = [
        (" 8000300: 4798         \tblx\tr3", Op::BranchReg),
        (" 8000300: 46f7         \tmov\tpc, lr", Op::BranchReg),
        (" 8000300: 4487         \tadd\tpc, r0", Op::BranchReg),
        (" 80027c8: e8df f000    \ttbb\t[pc, r0]", Op::Table),
        (" 800177c: e8df f010    \ttbh\t[pc, r0, lsl #1]", Op::Table),
        (" 80001c8: f3bf 8f4f    \tdsb\tsy", Op::Barrier),
        (" 80001c8: f3bf 8f5f    \tdmb\tsy", Op::Barrier),
        (" 80001cc: f3bf 8f6f    \tisb\tsy", Op::Isb),
        (" 80001f8: b672         \tcpsid i", Op::System),
        (" 8000300: f380 8811    \tmsr\tbasepri, r0", Op::System),
        (" 8000300: f3ef 8011    \tmrs\tr0, basepri", Op::System),
        (" 8000300: bf30         \twfi", Op::Hint),
        (" 8000300: bf20         \twfe", Op::Hint),
        (" 8000300: bf40         \tsev", Op::Hint),
        (" 8000300: bf10         \tyield", Op::Hint),
        (" 8000300: defe         \ttrap", Op::Trap),
        (" 8000300: df00         \tsvc\t#0x0", Op::Trap),
        (" 8000300: be00         \tbkpt\t#0x0", Op::Trap),
    ];
    for (line, op) in cases {
        let i = one(line);
        assert_eq!(i.op, op, "{line}");
        let branches = matches!(op, Op::BranchReg | Op::Table);
        assert_eq!(i.writes_pc(), branches, "{line}");
    }
    let mrs = one(" 8000300: f3ef 8011    \tmrs\tr0, basepri");
    assert_eq!(mrs.writes, regs(&[0]));
}

#[test]
fn multiplies_and_divides_name_their_registers() {
    let umull = one(" 8000300: fba0 2301    \tumull\tr2, r3, r0, r1");
    assert_eq!((umull.op, umull.writes, umull.reads), (Op::Mul, regs(&[2, 3]), regs(&[0, 1])));
    let umlal = one(" 8000300: fbe0 2301    \tumlal\tr2, r3, r0, r1");
    assert_eq!(umlal.reads, regs(&[0, 1, 2, 3]), "accumulates into r2:r3");
    let mla = one(" 8000300: fb00 c00b    \tmla\tr0, r0, r11, r12");
    assert_eq!((mla.op, mla.writes, mla.reads), (Op::Mul, regs(&[0]), regs(&[0, 11, 12])));
    let p = Program::parse(" 8000300: fbb0 f0f1    \tudiv\tr0, r0, r1\n 8000304: fb93 f1f1    \tsdiv\tr1, r3, r1");
    let d: Vec<Op> = p.divides().map(|i| i.op).collect();
    assert_eq!(
        d,
        [Op::Div { signed: false, dividend: 0, divisor: 1 }, Op::Div { signed: true, dividend: 3, divisor: 1 }]
    );
}

#[test]
fn suffixes_flags_and_conditions_are_told_apart() {
    let cases = [
        ("movs\tr0, #0x1", false),
        ("lsls\tr0, r1, #0x2", false),
        ("bics\tr0, r1", false),
        ("sbcs\tr0, r1", false),
        ("mulls\tr0, r1, r0", true),
        ("lslls\tr0, r1, #0x2", true),
        ("teq.w\tr1, #0x1", false),
        ("mls\tr0, r1, r0, r2", false),
        ("smlals\tr0, r1, r2, r3", false),
        ("addseq\tr0, #0x1", true),
        ("ldrhs\tr0, [r1]", true),
        ("ldrhhs\tr0, [r1]", true),
        ("popne.w\t{r7, lr}", true),
        ("dmbmi\tsy", true),
        ("bxhi\tlr", true),
        ("vaddeq.f32\ts0, s1, s2", true),
    ];
    for (text, cond) in cases {
        let i = one(&format!(" 8000300: 4000         \t{text}"));
        assert_eq!(i.conditional, cond, "{text}");
    }
}

#[test]
fn fpu_transfers_and_arithmetic() {
    let fp = |t: &str| one(&format!(" 8000300: ed2d 8b04    \t{t}")).op;
    assert_eq!(fp("vpush\t{d8, d9}"), Op::FpMem { words: 4 });
    assert_eq!(fp("vpop\t{s16-s31}"), Op::FpMem { words: 16 });
    assert_eq!(fp("vldr\td0, [r0, #8]"), Op::FpMem { words: 2 });
    assert_eq!(fp("vstr\ts0, [sp, #4]"), Op::FpMem { words: 1 });
    assert_eq!(fp("vldmia\tr0!, {s0-s3}"), Op::FpMem { words: 4 });
    assert_eq!(fp("vdiv.f32\ts0, s1, s2"), Op::Fp { cycles: 14, arith: true });
    assert_eq!(fp("vsqrt.f32\ts0, s1"), Op::Fp { cycles: 14, arith: true });
    assert_eq!(fp("vfma.f32\ts0, s1, s2"), Op::Fp { cycles: 3, arith: true });
    assert_eq!(fp("vcvt.s32.f32\ts0, s0"), Op::Fp { cycles: 1, arith: true });
    assert_eq!(fp("vcmpe.f32\ts0, #0"), Op::Fp { cycles: 1, arith: false });
    assert_eq!(fp("vmov\tr0, s0"), Op::Fp { cycles: 2, arith: false });
    assert_eq!(fp("vmov.32\tr0, d0[1]"), Op::Fp { cycles: 1, arith: false });
    assert_eq!(fp("vmov.f32\ts0, #1.000000e+00"), Op::Fp { cycles: 1, arith: false });
    let to_core = one(" 8000300: ee10 0a10    \tvmov\tr0, s0");
    assert_eq!(to_core.writes, regs(&[0]));
    let from_core = one(" 8000300: ee00 0a10    \tvmov\ts0, r0");
    assert_eq!((from_core.reads, from_core.writes), (regs(&[0]), 0));
}

#[test]
fn unknown_mnemonics_and_odd_lines_are_reported_not_dropped() {
    let p = Program::parse(" 8000300: 4000         \tfrobnicate\tr0\n 8000302: f8d1         \tldr.w\tr0, [r1]");
    assert_eq!(p.unknown().len(), 2, "{:?}", p.unknown());
    assert!(p.insns().is_empty());
}
