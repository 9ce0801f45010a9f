//! The timing rules on short sequences; the figures are the TRM's (ARM DDI
//! 0439D), each test naming the rule it holds.

use super::insn::Insn;
use super::program::Program;
use super::timing::{block_cost, block_cost_after, divide, refill, unaligned, Cost};

/// Instructions from `mnemonic\toperands` lines; `w:` marks a 32-bit encoding.
fn insns(src: &str) -> Vec<Insn> {
    let mut addr = 0x0800_0100u32;
    let mut text = String::new();
    for l in src.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let (raw, body, size) = match l.strip_prefix("w:") {
            Some(b) => ("f8d1 0004", b, 4),
            None => ("4000     ", l, 2),
        };
        text += &format!(" {addr:x}: {raw}    \t{}\n", body.replacen(' ', "\t", 1));
        addr += size;
    }
    let p = Program::parse(&text);
    assert!(p.unknown().is_empty(), "{:?}", p.unknown());
    p.insns().to_vec()
}

fn cost(src: &str) -> Cost {
    block_cost(&insns(src))
}

/// The block after a BL (a predecessor that computes nothing), so the bound's
/// unknown-predecessor allowance stays out of the figure.
fn cost_after_call(src: &str) -> Cost {
    let bl = insns("w:bl 0x8000000");
    block_cost_after(Some(&bl[0]), &insns(src))
}

fn c(model: u32, bound: u32) -> Cost {
    Cost { model, bound }
}

#[test]
fn neighbouring_loads_pipeline_in_the_model_only() {
    // §3.3.2: "LDR R0,[R1]; LDR R1,[R2] - normally three cycles total"
    assert_eq!(cost_after_call("ldr r0, [r1]\nldr r1, [r2]"), c(3, 4));
    // "LDR R0,[R1,R5]; LDR R1,[R2]; LDR R2,[R3,#4] - normally four cycles total"
    assert_eq!(cost_after_call("ldr r0, [r1, r5]\nldr r1, [r2]\nldr r2, [r3, #0x4]"), c(4, 6));
    // "LDR R0,[R1,R2]; STR R1,[R3,R2] - normally three cycles total"
    assert_eq!(cost_after_call("ldr r0, [r1, r2]\nstr r1, [r3, r2]"), c(3, 4));
    // "LDR R0,[R1,R2]; STR R0,[R3,#20] - normally three cycles total": the
    // store writes what the load loaded (data, not address)
    assert_eq!(cost_after_call("ldr r0, [r1, r2]\nstr r0, [r3, #0x14]"), c(3, 4));
}

#[test]
fn a_load_whose_address_needs_the_previous_load_is_not_pipelined() {
    assert_eq!(cost_after_call("ldr r0, [r1]\nldr r2, [r0]"), c(4, 4));
    assert_eq!(cost_after_call("ldr r0, [r1]\nldr r2, [r3, r0]"), c(4, 4));
}

#[test]
fn nothing_pipelines_after_a_store_or_around_ldrd_ldm() {
    // §3.3.2: "nothing can be pipelined after the store"
    assert_eq!(cost_after_call("str r0, [r1]\nldr r2, [r3]"), c(3, 4));
    assert_eq!(cost_after_call("str r0, [r1, r2]\nldr r2, [r3]"), c(4, 4));
    // "LDRD and STRD cannot be pipelined with preceding or following instructions"
    assert_eq!(cost_after_call("ldr r0, [r1]\nldrd r2, r3, [r4]"), c(5, 5));
    assert_eq!(cost_after_call("ldrd r2, r3, [r4]\nldr r0, [r1]"), c(5, 5));
    assert_eq!(cost_after_call("ldr r0, [r1]\nldm r2!, {r3, r4}"), c(5, 5));
}

#[test]
fn a_store_with_an_immediate_is_one_cycle_in_the_model_two_in_the_bound() {
    assert_eq!(cost_after_call("str r0, [r1, #0x4]"), c(1, 2));
    assert_eq!(cost_after_call("w:strb.w r0, [r1, #0x4]"), c(1, 2));
    assert_eq!(cost_after_call("str r0, [r1, r2]"), c(2, 2));
}

#[test]
fn an_address_computed_by_the_instruction_before_costs_one_more() {
    // §3.3.2: no forwarding path from a data-processing result to the address
    assert_eq!(cost_after_call("add r1, r2\nldr r0, [r1]"), c(4, 4));
    assert_eq!(cost_after_call("add r3, r2\nldr r0, [r1]"), c(3, 3), "independent");
    assert_eq!(cost_after_call("w:mul r1, r2, r3\nstr r0, [r1, #0x4]"), c(3, 4));
    assert_eq!(cost_after_call("sub sp, #0x8\npush {r4, lr}"), c(5, 5), "push's address is sp");
    assert_eq!(cost_after_call("add r1, r2\nnop\nldr r0, [r1]"), c(4, 4), "only the instruction just before");
}

#[test]
fn an_unknown_predecessor_costs_the_bound_an_interlock() {
    // push {r4-r7, lr}: Table 3-1 "1 + N"
    assert_eq!(cost_after_call("push {r4, r5, r6, r7, lr}"), c(6, 6));
    assert_eq!(cost("push {r4, r5, r6, r7, lr}"), c(6, 7));
    assert_eq!(cost("movs r0, #0x1"), c(1, 1), "not a load or store");
    assert_eq!(cost("ldr r0, [pc, #0x8]"), c(2, 3), "pc is never computed: only the literal's fetch contention");
}

#[test]
fn pairing_continues_across_the_block_boundary_when_the_caller_gives_the_predecessor() {
    let ld = insns("ldr r0, [r1]");
    assert_eq!(block_cost_after(Some(&ld[0]), &insns("ldr r2, [r3]")), c(1, 2));
    let add = insns("adds r3, #0x1");
    assert_eq!(block_cost_after(Some(&add[0]), &insns("ldr r2, [r3]")), c(3, 3));
}

#[test]
fn multiples_doubles_and_loads_to_the_pc() {
    assert_eq!(cost_after_call("w:ldrd r0, r1, [r2, #0x8]"), c(3, 3));
    assert_eq!(cost_after_call("w:strd r0, r1, [r2], #8"), c(3, 3));
    let pop = insns("pop {r4, pc}");
    assert_eq!(block_cost_after(Some(&insns("nop")[0]), &pop), c(3, 3), "1 + N");
    // §3.3.2: "LDR PC,[any] ... three cycles for the pipeline reload"
    assert_eq!(refill(&pop[0], 0x0800_0200, 2), c(3, 3));
    let ldpc = insns("w:ldr pc, [sp], #4");
    assert_eq!(block_cost_after(Some(&insns("nop")[0]), &ldpc) + refill(&ldpc[0], 0x0800_0200, 2), c(5, 5));
}

#[test]
fn a_branch_costs_one_not_taken_and_its_refill_when_taken() {
    let b = insns("cmp r0, #0x1\nbne 0x8000200");
    assert_eq!(block_cost(&b), c(2, 2), "not taken (Table 3-1 note c)");
    // (the model's one cycle more than the M3 TRM's "normally": CoreMark on
    // this board, `refill`'s doc)
    assert_eq!(refill(&b[1], 0x0800_0200, 2), c(2, 3), "taken, immediate target");
    assert_eq!(refill(&b[1], 0x0800_0202, 4), c(3, 3), "a 32-bit target straddling two words");
    assert_eq!(refill(&b[1], 0x0800_0204, 4), c(2, 3), "a word-aligned 32-bit target");
    assert_eq!(refill(&b[0], 0x0800_0200, 2), c(0, 0), "cmp writes no pc");
    let bx = insns("bx lr");
    assert_eq!(refill(&bx[0], 0x0800_0200, 2), c(3, 3), "register target");
    assert_eq!(refill(&bx[0], 0x0800_0202, 4), c(3, 3), "at most the bound's 3");
    let bl = insns("w:bl 0x8000200");
    assert_eq!(cost("w:bl 0x8000200") + refill(&bl[0], 0x0800_0200, 2), c(3, 4));
}

#[test]
fn a_table_branch_takes_at_least_six() {
    // §3.3.2: "at least two cycles for the load, one cycle for the add, and
    // three cycles for the pipeline reload. This means at least six cycles"
    let t = insns("w:tbb [pc, r0]");
    let total = block_cost_after(Some(&insns("nop")[0]), &t) + refill(&t[0], 0x0800_0200, 2);
    assert_eq!(total, c(6, 7), "the bound adds the pc-relative read's fetch contention");
}

#[test]
fn an_it_folds_onto_a_16_bit_instruction_in_the_model() {
    // Table 3-1 note d
    assert_eq!(cost("cmp r0, #0x1\nit eq\nmoveq r0, #0x2"), c(2, 3));
    assert_eq!(cost("w:cmp.w r0, #0x1\nit eq\nmoveq r0, #0x2"), c(3, 3), "after a 32-bit instruction");
    assert_eq!(cost("it eq\nmoveq r0, #0x2"), c(2, 2), "no predecessor seen");
}

#[test]
fn conditional_instructions_cost_as_executed() {
    assert_eq!(cost_after_call("itt ne\nldrne r0, [r1]\nstrne r0, [r2, #0x4]"), c(4, 5));
}

#[test]
fn system_barrier_hint_and_fpu_rows() {
    assert_eq!(cost("w:msr basepri, r0"), c(2, 2), "Table 3-1 '1 or 2'");
    assert_eq!(cost("cpsid i"), c(2, 2));
    assert_eq!(cost("w:dmb sy"), c(1, 1), "the drain is the caller's");
    assert_eq!(cost("w:isb sy"), c(2, 4), "1 + B, B at least a refill");
    assert_eq!(cost("wfi\nnop\nsev"), c(3, 3));
    assert_eq!(cost("w:vdiv.f32 s0, s1, s2"), c(14, 15));
    assert_eq!(cost("w:vadd.f32 s0, s1, s2"), c(1, 2));
    assert_eq!(cost("w:vcmp.f32 s0, s1"), c(1, 1));
    assert_eq!(cost_after_call("w:vpush {d8, d9, d10, d11, d12, d13, d14, d15}"), c(17, 17), "1 + 2N doubles");
    assert_eq!(cost_after_call("w:vldr s0, [r0, #4]"), c(2, 2));
    assert_eq!(cost_after_call("w:vstr d0, [r0, #8]"), c(3, 3));
    assert_eq!(cost("w:vmov r0, s0"), c(2, 2));
}

#[test]
fn a_divide_costs_the_minimum_in_the_block_and_its_operands_decide_the_model() {
    assert_eq!(cost("w:udiv r0, r0, r1"), c(2, 12));
    assert_eq!(divide(5, 0, false), c(2, 12), "by zero: the minimum");
    assert_eq!(divide(5, 6, false), c(2, 12), "quotient 0: the minimum");
    assert_eq!(divide(u32::MAX, 1, false), c(12, 12), "a 32-bit quotient: the maximum");
    assert_eq!(divide(100, 10, false), c(4, 12), "a 4-bit quotient");
    assert_eq!(divide(-100i32 as u32, 10, true), c(4, 12), "signed by magnitude");
    assert_eq!(divide(-100i32 as u32, 10, false), c(12, 12), "the same bits unsigned: a 29-bit quotient");
    assert_eq!(divide(1 << 16, 1, false), c(8, 12), "a 17-bit quotient: 2 + ceil(170 / 32)");
    for (n, d) in [(1u32, 1u32), (7, 3), (1 << 31, 3), (12345, 17)] {
        let m = divide(n, d, false).model;
        assert!((2..=12).contains(&m), "{n}/{d}: {m}");
    }
}

#[test]
fn unaligned_accesses_add_the_trm_penalties() {
    assert_eq!(unaligned(0x2000_0001, 2, false), c(1, 1), "byte-aligned halfword");
    assert_eq!(unaligned(0x2000_0002, 4, false), c(1, 1), "halfword-aligned word");
    assert_eq!(unaligned(0x2000_0003, 4, false), c(2, 2), "byte-aligned word");
    assert_eq!(unaligned(0x2000_0003, 4, true), c(0, 2), "a store waits in the write buffer");
    assert_eq!(unaligned(0x2000_0004, 4, false), c(0, 0));
    assert_eq!(unaligned(0x2000_0001, 1, false), c(0, 0));
}
