//! The image's instructions, read from `llvm-objdump -d` with raw bytes
//! shown. Code lines print their encoding as halfwords (`f8d1 0004`, so the
//! size is known); data that the ELF's mapping symbols mark (`$d`: literal
//! pools, jump tables) prints as bytes with a `.word`/`.short`/`.byte`
//! directive and is skipped.

use super::decode::build;
use super::insn::{Insn, Op};
use super::mnemonic::classify;
use polyturn_stm32_model::addr::FLASH_BASE;

#[derive(Default)]
pub struct Program {
    insns: Vec<Insn>,
    unknown: Vec<(u32, String)>,
}

impl Program {
    pub fn parse(objdump_text: &str) -> Program {
        let mut p = Program::default();
        let mut it_left = 0u8;
        for line in objdump_text.lines() {
            match parse_line(line) {
                Line::Code(mut insn) => {
                    insn.conditional |= it_left > 0;
                    it_left = match insn.op {
                        Op::It { count } => count,
                        _ => it_left.saturating_sub(1),
                    };
                    p.insns.push(insn);
                }
                Line::Unknown(addr, why) => p.unknown.push((addr, why)),
                Line::Other => {}
            }
        }
        p.insns.sort_by_key(|i| i.addr);
        p
    }

    #[cfg(test)]
    pub fn insns(&self) -> &[Insn] {
        &self.insns
    }

    /// The instructions in [addr, addr + size) in order (a translated block);
    /// addresses in the boot alias at 0 map to flash.
    pub fn block(&self, addr: u32, size: u32) -> &[Insn] {
        let found = self.range(addr, size);
        if found.is_empty() && addr < FLASH_BASE {
            // code linked at its own address below flash (SRAM mapped at 0)
            // comes first; else the boot alias of flash
            return self.range(FLASH_BASE + addr, size);
        }
        found
    }

    fn range(&self, start: u32, size: u32) -> &[Insn] {
        let end = start.saturating_add(size);
        let lo = self.insns.partition_point(|i| i.addr < start);
        let hi = self.insns.partition_point(|i| i.addr < end);
        &self.insns[lo..hi.max(lo)]
    }

    #[cfg(test)]
    pub fn at(&self, addr: u32) -> Option<&Insn> {
        let find = |a: u32| self.insns.binary_search_by_key(&a, |i| i.addr).ok().map(|k| &self.insns[k]);
        find(addr).or_else(|| (addr < FLASH_BASE).then(|| find(FLASH_BASE + addr)).flatten())
    }

    /// Lines the parser could not read: must be empty for the real image.
    pub fn unknown(&self) -> &[(u32, String)] {
        &self.unknown
    }

    /// The SDIV/UDIV instructions: the caller reads their operands to time them.
    pub fn divides(&self) -> impl Iterator<Item = &Insn> {
        self.insns.iter().filter(|i| matches!(i.op, Op::Div { .. }))
    }
}

enum Line {
    Code(Insn),
    Unknown(u32, String),
    Other,
}

/// ` 8000abc: f8d1 0004   \tldr.w\tr0, [r1, #4]   @ comment`
fn parse_line(line: &str) -> Line {
    let Some((addr, rest)) = line.trim_start().split_once(':') else { return Line::Other };
    let Ok(addr) = u32::from_str_radix(addr, 16) else { return Line::Other };
    let mut fields = rest.splitn(2, '\t');
    let raw: Vec<&str> = fields.next().unwrap_or("").split_whitespace().collect();
    let text = fields.next().unwrap_or("").trim();
    if text.starts_with('.') {
        return Line::Other; // data under a `$d` mapping symbol
    }
    let halfwords: Vec<u16> =
        raw.iter().filter(|w| w.len() == 4).filter_map(|w| u16::from_str_radix(w, 16).ok()).collect();
    if halfwords.is_empty() || halfwords.len() != raw.len() || halfwords.len() > 2 {
        return Line::Unknown(addr, format!("unreadable line: {}", line.trim()));
    }
    // ARMv7-M ARM §A5.1: a first halfword 0b11101/0b11110/0b11111 starts a 32-bit instruction
    let size = if matches!(halfwords[0] >> 11, 0x1D..=0x1F) { 4 } else { 2 };
    if size != 2 * halfwords.len() {
        return Line::Unknown(addr, format!("{} halfwords shown for a {size}-byte encoding: {}", raw.len(), text));
    }
    let (text, comment) = text.split_once('@').unwrap_or((text, ""));
    let (mnemonic, ops) = text.trim().split_once(char::is_whitespace).unwrap_or((text.trim(), ""));
    let mnemonic = mnemonic.to_ascii_lowercase();
    let Some((kind, cond)) = classify(&mnemonic) else {
        return Line::Unknown(addr, format!("unknown mnemonic: {}", text.trim()));
    };
    match build(addr, kind, &mnemonic, ops.trim(), comment) {
        Ok(mut insn) => {
            insn.size = size as u8;
            insn.conditional |= cond;
            Line::Code(insn)
        }
        Err(why) => Line::Unknown(addr, format!("{why}: {}", text.trim())),
    }
}
