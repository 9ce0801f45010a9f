//! The parser on the real firmware image (`cargo fw` builds it; without it
//! these checks print a note and pass: they cannot look at what is not there).

use super::insn::Op;
use super::program::Program;
use crate::image::Image;
use crate::machine::insn_count;
use std::collections::BTreeMap;
use std::path::PathBuf;

fn elf() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"));
    target.join("thumbv7em-none-eabihf/fw/polyturn-firmware")
}

fn real_image() -> Option<(Program, Image)> {
    let path = elf();
    if !path.exists() {
        eprintln!(
            "note: no firmware image at {}: the real-image checks are skipped (build it: cargo fw)",
            path.display()
        );
        return None;
    }
    let text = crate::disasm::text(&path).expect("llvm-objdump on the image");
    let image = crate::image::load(&path).expect("the image loads");
    Some((Program::parse(&text), image))
}

/// The image's bytes at [addr, addr + len), from its loadable segments.
fn bytes(image: &Image, addr: u32, len: u32) -> &[u8] {
    let addr = image.load_address_of(addr);
    let (base, data) = image
        .segments
        .iter()
        .find(|(b, d)| *b <= addr && addr + len <= b + d.len() as u32)
        .unwrap_or_else(|| panic!("{addr:#x} is in no segment"));
    &data[(addr - base) as usize..(addr - base + len) as usize]
}

#[test]
fn every_line_of_the_real_image_is_understood() {
    let Some((p, _)) = real_image() else { return };
    assert!(p.insns().len() > 10_000, "{} instructions: not the whole image?", p.insns().len());
    let shown: Vec<_> = p.unknown().iter().take(20).collect();
    assert!(p.unknown().is_empty(), "{} lines not understood, the first: {shown:#x?}", p.unknown().len());
}

#[test]
fn the_real_images_sizes_match_its_bytes() {
    let Some((p, image)) = real_image() else { return };
    for i in p.insns() {
        let b = bytes(&image, i.addr, 2);
        let first = u16::from_le_bytes([b[0], b[1]]);
        let size = if matches!(first >> 11, 0x1D..=0x1F) { 4 } else { 2 };
        assert_eq!(i.size, size, "{:#x}: first halfword {first:#06x}", i.addr);
    }
}

/// Per function, the instructions the table holds equal what `insn_count`
/// (the machine's clock today) decodes from the same bytes: each run of
/// contiguous code between data is decoded on its own.
#[test]
fn per_function_counts_match_insn_count_on_the_bytes() {
    let Some((p, image)) = real_image() else { return };
    let mut per_fn: BTreeMap<String, (u64, u64)> = BTreeMap::new();
    let insns = p.insns();
    let mut start = 0;
    for k in 1..=insns.len() {
        let (a, func) = (&insns[start], image.func_at(insns[start].addr));
        let run_ends = k == insns.len()
            || insns[k].addr != insns[k - 1].addr + insns[k - 1].size as u32
            || image.func_at(insns[k].addr) != func;
        if run_ends {
            let end = insns[k - 1].addr + insns[k - 1].size as u32;
            let e = per_fn.entry(func).or_default();
            e.0 += (k - start) as u64;
            e.1 += insn_count(bytes(&image, a.addr, end - a.addr));
            start = k;
        }
    }
    let wrong: Vec<_> = per_fn.iter().filter(|(_, (table, decoded))| table != decoded).take(10).collect();
    assert!(per_fn.len() > 100, "{} functions", per_fn.len());
    assert!(wrong.is_empty(), "(table, insn_count) differ: {wrong:?}");
}

/// Checks the branch-target and literal parsing, and that no code was taken
/// for data: every branch inside a function lands on an instruction, every
/// literal on data. (The linker's fill between functions disassembles as
/// branches to nowhere: it is never run.)
#[test]
fn the_real_images_branches_land_on_instructions_and_literals_on_data() {
    let Some((p, image)) = real_image() else { return };
    let (mut branches, mut literals) = (0, 0);
    for i in p.insns().iter().filter(|i| image.in_function(i.addr)) {
        match i.op {
            Op::Branch { target } | Op::Call { target } => {
                branches += 1;
                assert!(p.at(target).is_some(), "{:#x}: target {target:#x} is no instruction", i.addr);
            }
            Op::Single { literal: Some(at), .. } | Op::Double { literal: Some(at) } => {
                literals += 1;
                assert!(p.at(at).is_none(), "{:#x}: literal {at:#x} is an instruction", i.addr);
            }
            _ => {}
        }
    }
    // (at opt-level "s" LLVM builds most constants with MOVW/MOVT: few
    // literal pools are left, but some are)
    assert!(branches > 1000 && literals > 0, "{branches} branches, {literals} literal loads");
}
