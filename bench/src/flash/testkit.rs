//! Images for tests, built here rather than taken from a firmware build: a
//! vector table that starts, code-like bytes, a marker, the seal; and a
//! minimal ELF32 (header and program headers only, as the checks read them).

use polyturn_host::flash::{seal, FLASH_BASE};

pub const GOOD_MARKER: &[u8] = b"polyturn-image:stm32f411ce:0.1.0\0";
/// Reset handler at 0x08000198 (Thumb: odd), where cortex-m-rt puts it.
pub const RESET: u32 = FLASH_BASE + 0x199;
pub const SP: u32 = 0x2002_0000;

/// `len` bytes: the vector table, a marker at 0x200 when `marker` is not
/// empty, and bytes with every bit pattern (none all-0xFF runs).
pub fn image_with(len: usize, sp: u32, reset: u32, marker: &[u8]) -> Vec<u8> {
    let mut b: Vec<u8> = (0..len).map(|i| (i.wrapping_mul(151) ^ (i >> 8)) as u8).collect();
    let mut put = |at: usize, bytes: &[u8]| {
        if let Some(dst) = b.get_mut(at..at + bytes.len()) {
            dst.copy_from_slice(bytes);
        }
    };
    put(0, &sp.to_le_bytes());
    put(4, &reset.to_le_bytes());
    // the system exceptions' handlers (PM0214 Table 17), reserved words 0
    for n in 2..16 {
        let handler = if matches!(n, 7..=10 | 13) { 0 } else { RESET };
        put(4 * n, &handler.to_le_bytes());
    }
    put(0x200, marker);
    b
}

/// A polyturn image as an ELF holds it (`len` bytes, marked, no seal).
pub fn unsealed(len: usize) -> Vec<u8> {
    image_with(len, SP, RESET, GOOD_MARKER)
}

/// A release image: `unsealed(len)` padded to a word and sealed, as
/// `polyturn image` writes it (`len` rounded up to 4, plus 12 bytes).
pub fn good(len: usize) -> Vec<u8> {
    let mut b = unsealed(len);
    seal::seal(&mut b);
    b
}

/// An ELF32 for ARM, little-endian, with PT_LOAD segments (paddr, vaddr,
/// bytes, memsz beyond the bytes).
pub fn elf(segments: &[(u32, u32, &[u8], u32)]) -> Vec<u8> {
    elf_for(40, segments)
}

pub fn elf_for(machine: u16, segments: &[(u32, u32, &[u8], u32)]) -> Vec<u8> {
    let phnum = segments.len() as u16;
    let mut data_at = 52 + 32 * segments.len() as u32;
    let mut out = vec![0x7f, b'E', b'L', b'F', 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    let h16 = |out: &mut Vec<u8>, v: u16| out.extend_from_slice(&v.to_le_bytes());
    let h32 = |out: &mut Vec<u8>, v: u32| out.extend_from_slice(&v.to_le_bytes());
    h16(&mut out, 2); // ET_EXEC
    h16(&mut out, machine);
    h32(&mut out, 1);
    h32(&mut out, RESET);
    h32(&mut out, 52); // e_phoff
    h32(&mut out, 0); // e_shoff
    h32(&mut out, 0x0500_0400); // EABI5, hard float
    for v in [52, 32, phnum, 40, 0, 0] {
        h16(&mut out, v);
    }
    for (paddr, vaddr, bytes, extra) in segments {
        let n = bytes.len() as u32;
        for v in [1, data_at, *vaddr, *paddr, n, n + extra, 5, 4] {
            h32(&mut out, v);
        }
        data_at += n;
    }
    for (_, _, bytes, _) in segments {
        out.extend_from_slice(bytes);
    }
    out
}

/// An Intel HEX record line with its checksum.
pub fn record(kind: u8, offset: u16, data: &[u8]) -> String {
    let mut bytes = vec![data.len() as u8, (offset >> 8) as u8, offset as u8, kind];
    bytes.extend_from_slice(data);
    let sum = bytes.iter().fold(0u8, |s, b| s.wrapping_add(*b)).wrapping_neg();
    bytes.push(sum);
    format!(":{}", bytes.iter().map(|b| format!("{b:02X}")).collect::<String>())
}
