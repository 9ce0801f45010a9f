//! A firmware image as it will lie in flash: its bytes from FLASH_BASE,
//! gaps filled with 0xFF (what an erased flash byte reads, RM0383 §3.5.3),
//! read from a `.bin`, an Intel `.hex` or an ELF, and checked (`check.rs`)
//! before any USB request is sent.

use super::{check, elf, hex, seal, Canvas, Image, Refusal, FLASH_BASE};
use sha2::{Digest, Sha256};
use std::io::Read;
use std::path::Path;

/// A firmware ELF with debug info (the fw profile keeps debug = 2) is
/// about 30 times its 75 KiB image; 16 MiB leaves room and bounds a read.
pub const FILE_MAX_BYTES: u64 = 16 << 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Bin,
    Hex,
    Elf,
}

/// Reads, recognises and checks one file. `any_image` accepts an image
/// without a polyturn marker (every address and vector check still holds).
pub fn load(path: &Path, any_image: bool) -> Result<Image, Refusal> {
    let bytes = read_bounded(path)?;
    let format = format_of(path, &bytes)?;
    from_bytes(&bytes, format, any_image)
}

/// The image a file holds, checked. An ELF with the polyturn marker is
/// sealed here, as `polyturn image` seals it (`seal.rs`): flashing the ELF
/// writes the same bytes as its release `.bin`.
pub fn from_bytes(file: &[u8], format: Format, any_image: bool) -> Result<Image, Refusal> {
    let (base, mut bytes) = match format {
        Format::Bin => {
            let mut c = Canvas::new();
            c.place(FLASH_BASE, file, "the data")?;
            c.finish()?
        }
        Format::Hex => hex::parse(file)?,
        Format::Elf => elf::parse(file)?,
    };
    if format == Format::Elf && check::marked(&bytes) {
        seal::seal(&mut bytes);
    }
    let version = check::image(base, &bytes, any_image)?;
    let sha256 = Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
    Ok(Image { base, bytes, version, sha256 })
}

/// A regular file (not `/dev/zero`, a FIFO or a directory, which could
/// block or never end), read up to FILE_MAX_BYTES.
pub fn read_bounded(path: &Path) -> Result<Vec<u8>, Refusal> {
    let meta = std::fs::metadata(path).map_err(|e| Refusal::new("must be a readable file", e.to_string()))?;
    if !meta.is_file() {
        return Err(Refusal::new("must be a regular file (a .bin, .hex or ELF)", "not a regular file"));
    }
    let f = std::fs::File::open(path).map_err(|e| Refusal::new("must be a readable file", e.to_string()))?;
    let mut bytes = Vec::new();
    f.take(FILE_MAX_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Refusal::new("must be a readable file", e.to_string()))?;
    if bytes.len() as u64 > FILE_MAX_BYTES {
        let rule = format!("must be at most {FILE_MAX_BYTES} bytes (a firmware ELF with debug info is about 2 MB)");
        return Err(Refusal::new(rule, format!("larger than {FILE_MAX_BYTES} bytes")));
    }
    Ok(bytes)
}

/// ELF by its magic; then `.hex`/`.bin` by the name; else Intel HEX if it
/// starts with a record's ':', raw binary otherwise.
/// Text that starts with a HEX record's ':' and is printable ASCII.
fn looks_like_hex(bytes: &[u8]) -> bool {
    bytes.first() == Some(&b':') && bytes.iter().all(|b| b.is_ascii_graphic() || b.is_ascii_whitespace())
}

pub fn format_of(path: &Path, bytes: &[u8]) -> Result<Format, Refusal> {
    if bytes.starts_with(b"\x7fELF") {
        return Ok(Format::Elf);
    }
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    match ext.as_str() {
        "hex" | "ihex" | "ihx" => Ok(Format::Hex),
        // a raw image starts with the stack pointer, never a text line
        "bin" if looks_like_hex(bytes) => Err(Refusal::new(
            "must be an ELF, .hex or .bin file",
            "named .bin but it is Intel HEX text (lines starting ':'): name it .hex",
        )),
        "bin" => Ok(Format::Bin),
        "elf" => Err(Refusal::new("must be an ELF, .hex or .bin file", "named .elf but not an ELF file")),
        _ if bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b':') => Ok(Format::Hex),
        _ => Ok(Format::Bin),
    }
}
