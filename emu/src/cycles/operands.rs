//! The operand text of llvm-objdump's ARM (UAL) syntax: core registers,
//! register lists, memory operands and immediates.

/// A core register's number from its UAL name or the alias llvm-objdump
/// may print for it (ARMv7-M ARM §A2.3.1: r13 sp, r14 lr, r15 pc; the AAPCS
/// names ip r12, fp r11, sl r10, sb r9).
pub fn reg(name: &str) -> Option<u8> {
    match name {
        "sp" => Some(13),
        "lr" => Some(14),
        "pc" => Some(15),
        "ip" => Some(12),
        "fp" => Some(11),
        "sl" => Some(10),
        "sb" => Some(9),
        _ => name.strip_prefix('r')?.parse().ok().filter(|&n| n < 16),
    }
}

pub fn bit(r: u8) -> u16 {
    1 << r
}

/// The core registers named anywhere in `s` (words split at anything not a
/// letter or digit, so `lsl`, `#0x4`, `s0`, `basepri` name none).
pub fn regs_in(s: &str) -> u16 {
    s.split(|c: char| !c.is_ascii_alphanumeric()).filter_map(reg).fold(0, |m, r| m | bit(r))
}

/// The operands at the top level: commas inside `[...]` and `{...}` do not split.
pub fn split_top(s: &str) -> Vec<&str> {
    let (mut out, mut depth, mut start) = (Vec::new(), 0i32, 0);
    for (i, c) in s.char_indices() {
        match c {
            '[' | '{' => depth += 1,
            ']' | '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(s[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    if !s[start..].trim().is_empty() {
        out.push(s[start..].trim());
    }
    out
}

/// A register list such as `{r4, r5, r7, lr}`, `{r4-r11, pc}` or `{d8-d15}`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct List {
    /// core registers, bit n = rn
    pub core: u16,
    /// how many core registers the list names
    pub count: u8,
    /// 32-bit words of FP registers: s<n> one, d<n> two
    pub fp_words: u8,
}

pub fn list(s: &str) -> Option<List> {
    let inner = s.trim().strip_prefix('{')?.strip_suffix('}')?;
    let mut l = List::default();
    for item in inner.split(',').map(str::trim) {
        let (lo, hi) = item.split_once('-').unwrap_or((item, item));
        let (lo, hi) = (lo.trim(), hi.trim());
        if let (Some(a), Some(b)) = (reg(lo), reg(hi)) {
            for r in a..=b {
                l.core |= bit(r);
                l.count += 1;
            }
        } else {
            let (wide, a, b) = fp_range(lo, hi)?;
            l.fp_words += (b.checked_sub(a)? + 1) * if wide { 2 } else { 1 };
        }
    }
    Some(l)
}

/// An FP register range `s16`..`s31` or `d8`..`d15`: (double, first, last).
fn fp_range(lo: &str, hi: &str) -> Option<(bool, u8, u8)> {
    let wide = lo.starts_with('d');
    let num = |r: &str, p: char| r.strip_prefix(p)?.parse::<u8>().ok();
    let p = if wide { 'd' } else { 's' };
    Some((wide, num(lo, p)?, num(hi, p)?))
}

/// Whether `s` names an FP register (`s0`..`s31`, `d0`..`d15`, or a scalar `d0[1]`).
pub fn is_fp_reg(s: &str) -> bool {
    let name = s.split('[').next().unwrap_or(s);
    fp_range(name, name).is_some_and(|(wide, n, _)| n < if wide { 16 } else { 32 })
}

/// A memory operand `[rn, #imm]`, `[rn, rm, lsl #2]`, `[rn]!` or `[rn], #imm`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Mem {
    /// the registers inside the brackets: the address's base and index
    pub addr_regs: u16,
    pub base: Option<u8>,
    /// a register offset inside the brackets
    pub index: Option<u8>,
    /// the immediate offset inside the brackets
    pub imm: Option<i64>,
    /// `!` or a post-index operand: the base is written back
    pub writeback: bool,
    /// a register post-index offset (read, not part of the address)
    pub post_regs: u16,
}

/// The memory operand among `ops` (the first that opens a bracket), with any
/// post-index operand that follows it.
pub fn mem(ops: &[&str]) -> Option<Mem> {
    let at = ops.iter().position(|o| o.starts_with('['))?;
    let op = ops[at];
    let close = op.find(']')?;
    let inner = &op[1..close];
    let parts: Vec<&str> = inner.split(',').map(str::trim).collect();
    let post = ops.get(at + 1..).unwrap_or(&[]);
    Some(Mem {
        addr_regs: regs_in(inner),
        base: parts.first().and_then(|b| reg(b)),
        index: parts.get(1).and_then(|x| reg(x)),
        imm: parts.iter().find_map(|p| imm(p)),
        writeback: op[close..].contains('!') || !post.is_empty(),
        post_regs: post.iter().fold(0, |m, p| m | regs_in(p)),
    })
}

/// An immediate `#12`, `#0x38`, `#-0x10`.
pub fn imm(s: &str) -> Option<i64> {
    let s = s.trim().strip_prefix('#')?;
    let (neg, s) = s.strip_prefix('-').map_or((false, s), |r| (true, r));
    let v = match s.strip_prefix("0x") {
        Some(h) => i64::from_str_radix(h, 16).ok()?,
        None => s.parse().ok()?,
    };
    Some(if neg { -v } else { v })
}

/// The first absolute address `0x...` in `s` (branch targets, objdump's
/// literal-address comments).
pub fn address(s: &str) -> Option<u32> {
    s.split_whitespace().find_map(|w| u32::from_str_radix(w.strip_prefix("0x")?, 16).ok())
}
