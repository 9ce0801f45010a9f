//! Intel HEX, the 32-bit kind (I32HEX) that objcopy and STM32CubeProgrammer
//! use: data, end-of-file, extended linear address and start linear address
//! records; checksums checked by the `ihex` crate. The segment records of
//! 8086 I16HEX have no meaning for a Cortex-M and are refused.

use super::image::{Canvas, Image, Refusal};
use ihex::Record;

const HEX_RULE: &str = "must be Intel HEX: data, end-of-file and extended/start linear address records";

/// The image a .hex file describes, gaps 0xFF.
pub fn parse(file: &[u8]) -> Result<(u32, Vec<u8>), Refusal> {
    let text = std::str::from_utf8(file).map_err(|_| Refusal::new(HEX_RULE, "not text"))?;
    let mut canvas = Canvas::new();
    let mut upper: u32 = 0;
    let mut ended = false;
    for (i, line) in text.lines().enumerate() {
        let (n, line) = (i + 1, line.trim());
        if line.is_empty() {
            continue;
        }
        if ended {
            return Err(Refusal::new(HEX_RULE, format!("line {n} comes after the end-of-file record")));
        }
        let record = Record::from_record_string(line).map_err(|e| Refusal::new(HEX_RULE, format!("line {n}: {e}")))?;
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
            // the vector table gives the reset address; the bootloader
            // jumps through it (AN3156 §5.5)
            Record::StartLinearAddress(_) => {}
            Record::EndOfFile => ended = true,
            Record::ExtendedSegmentAddress(_) | Record::StartSegmentAddress { .. } => {
                return Err(Refusal::new(HEX_RULE, format!("line {n} is an 8086 segment record")));
            }
        }
    }
    if !ended {
        return Err(Refusal::new(HEX_RULE, "no end-of-file record (cut short?)"));
    }
    canvas.finish()
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
