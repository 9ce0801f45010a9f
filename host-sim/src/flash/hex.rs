//! Intel HEX, the 32-bit kind (I32HEX) that objcopy and STM32CubeProgrammer
//! use: data, end-of-file, extended linear address and start linear address
//! records; checksums checked by the `ihex` crate. The segment records of
//! 8086 I16HEX have no meaning for a Cortex-M and are refused. Nothing is
//! skipped unread: a blank line or spaces around a record (a file edited
//! or pasted by hand) is refused, and so is a start address that is not
//! the reset address the bootloader will jump through.

use super::{Canvas, Image, Refusal};
use ihex::Record;

const HEX_RULE: &str = "must be Intel HEX: data, end-of-file and extended/start linear address records";
const LINE_RULE: &str = "must be Intel HEX as a tool writes it: one record on every line, nothing around it";
const START_RULE: &str = "must give at most one start address, the reset address of its vector table";

/// The image a .hex file describes, gaps 0xFF.
pub fn parse(file: &[u8]) -> Result<(u32, Vec<u8>), Refusal> {
    let text = std::str::from_utf8(file).map_err(|_| Refusal::new(HEX_RULE, "not text"))?;
    let mut canvas = Canvas::new();
    let mut upper: u32 = 0;
    let mut ended = false;
    let mut start: Option<(usize, u32)> = None;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        bare(line, n)?;
        if ended {
            return Err(Refusal::new(HEX_RULE, format!("line {n} comes after the end-of-file record")));
        }
        let record =
            Record::from_record_string(line).map_err(|e| Refusal::new(HEX_RULE, format!("line {n}: {}", unread(e))))?;
        match record {
            Record::Data { offset, value } => {
                // a record wraps within its 64 KiB segment (I32HEX), which
                // no linker writes: refused rather than guessed
                if usize::from(offset) + value.len() > 0x1_0000 {
                    return Err(Refusal::new(HEX_RULE, format!("line {n} crosses a 64 KiB boundary")));
                }
                canvas.place(upper | u32::from(offset), &value, &format!("line {n}"))?;
            }
            Record::ExtendedLinearAddress(high) => upper = u32::from(high) << 16,
            Record::StartLinearAddress(_) if start.is_some() => {
                return Err(Refusal::new(START_RULE, format!("line {n}: a second start address")));
            }
            Record::StartLinearAddress(address) => start = Some((n, address)),
            Record::EndOfFile => ended = true,
            Record::ExtendedSegmentAddress(_) | Record::StartSegmentAddress { .. } => {
                return Err(Refusal::new(HEX_RULE, format!("line {n} is an 8086 segment record")));
            }
        }
    }
    if !ended {
        return Err(Refusal::new(HEX_RULE, "no end-of-file record (cut short?)"));
    }
    let gap = canvas.gap();
    let (base, bytes) = canvas.finish()?;
    whole(gap, &bytes)?;
    if let Some((n, address)) = start {
        starts_at_reset(&bytes, n, address)?;
    }
    Ok((base, bytes))
}

/// `polyturn image` writes every byte of a sealed polyturn image, so a gap
/// in one is a record missing (a HEX of another program, or an unsealed
/// one, may have gaps: they are erased flash). Said so, before the seal
/// would call it a changed byte.
fn whole(gap: Option<(u32, usize)>, bytes: &[u8]) -> Result<(), Refusal> {
    match gap {
        Some((at, len)) if super::check::marked(bytes) && super::seal::ends_sealed(bytes) => Err(Refusal::new(
            "must give every byte of a polyturn image, as `polyturn image` writes it",
            format!("no record gives 0x{at:08x}..0x{:08x} ({len} bytes): a record is missing", at as usize + len),
        )),
        _ => Ok(()),
    }
}

/// A line that is a record and nothing else.
fn bare(line: &str, n: usize) -> Result<(), Refusal> {
    if line.trim().is_empty() {
        return Err(Refusal::new(LINE_RULE, format!("line {n} is blank")));
    }
    if line.trim() != line {
        return Err(Refusal::new(LINE_RULE, format!("line {n} has spaces or tabs around its record")));
    }
    Ok(())
}

/// The bootloader jumps through the vector table, not to the start
/// address (AN3156 §5.5): one that differs says the file is not what it
/// seems (hand-edited, or joined from two builds). Bit 0 (Thumb) aside.
fn starts_at_reset(bytes: &[u8], n: usize, address: u32) -> Result<(), Refusal> {
    // too short for a reset vector: check.rs refuses it, saying so
    let Some(w) = bytes.get(4..8) else { return Ok(()) };
    let reset = u32::from_le_bytes([w[0], w[1], w[2], w[3]]);
    if address & !1 == reset & !1 {
        return Ok(());
    }
    Err(Refusal::new(
        START_RULE,
        format!("line {n}: start address 0x{address:08x}, not the vector table's reset address 0x{reset:08x}"),
    ))
}

/// The image as I32HEX text: 16 bytes a record as objcopy writes them,
/// the reset address as the start address, one end-of-file record.
pub fn write(image: &Image) -> Result<String, Refusal> {
    let mut records = Vec::with_capacity(image.bytes.len() / 16 + 8);
    let mut upper = None;
    for (i, chunk) in image.bytes.chunks(16).enumerate() {
        let address = image.base + (i as u32) * 16;
        if upper != Some(address >> 16) {
            upper = Some(address >> 16);
            records.push(Record::ExtendedLinearAddress((address >> 16) as u16));
        }
        records.push(Record::Data { offset: address as u16, value: chunk.to_vec() });
    }
    if let Some(w) = image.bytes.get(4..8) {
        records.push(Record::StartLinearAddress(u32::from_le_bytes([w[0], w[1], w[2], w[3]])));
    }
    records.push(Record::EndOfFile);
    ihex::create_object_file_representation(&records)
        .map_err(|e| Refusal::new("must be writable as Intel HEX", e.to_string()))
}

/// Why a record could not be read. The `ihex` crate's checksum message
/// names the sum it computed as the one found: told here the other way
/// round, the file's byte first.
fn unread(e: ihex::ReaderError) -> String {
    match e {
        ihex::ReaderError::ChecksumMismatch(computed, in_file) => {
            format!("checksum {in_file:02X} does not match the record, whose bytes make {computed:02X}")
        }
        e => e.to_string(),
    }
}
