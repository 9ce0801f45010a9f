//! A firmware image as it will lie in flash: its bytes from FLASH_BASE,
//! gaps filled with 0xFF (what an erased flash byte reads, RM0383 §3.5.3),
//! read from a `.bin`, an Intel `.hex` or an ELF, and checked (`check.rs`)
//! before any USB request is sent.

use super::{check, elf, hex, APP_END, FLASH_BASE, SECTOR_KIB};
use sha2::{Digest, Sha256};
use std::io::Read;
use std::path::Path;

/// A firmware ELF with debug info (the fw profile keeps debug = 2) is
/// about 30 times its 75 KiB image; 16 MiB leaves room and bounds a read.
pub const FILE_MAX_BYTES: u64 = 16 << 20;
/// The image's largest size: sectors 0-5 (memory.x FLASH LENGTH).
pub const IMAGE_MAX_BYTES: u32 = APP_END - FLASH_BASE;

/// A checked image, ready to flash at `base`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    pub base: u32,
    pub bytes: Vec<u8>,
    /// From the image's marker; `None` only with `--any-image`.
    pub version: Option<String>,
    /// SHA-256 of `bytes` (the `.bin`), lower-case hex.
    pub sha256: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Bin,
    Hex,
    Elf,
}

/// Why a file is no image to flash: the rule it breaks, and what it has.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    pub rule: String,
    pub found: String,
}

impl Refusal {
    pub fn new(rule: impl Into<String>, found: impl Into<String>) -> Refusal {
        Refusal { rule: rule.into(), found: found.into() }
    }
}

/// Reads, recognises and checks one file. `any_image` accepts an image
/// without a polyturn marker (every address and vector check still holds).
pub fn load(path: &Path, any_image: bool) -> Result<Image, Refusal> {
    let bytes = read_bounded(path)?;
    let format = format_of(path, &bytes)?;
    from_bytes(&bytes, format, any_image)
}

pub fn from_bytes(file: &[u8], format: Format, any_image: bool) -> Result<Image, Refusal> {
    let (base, bytes) = match format {
        Format::Bin => {
            let mut c = Canvas::new();
            c.place(FLASH_BASE, file, "the data")?;
            c.finish()?
        }
        Format::Hex => hex::parse(file)?,
        Format::Elf => elf::parse(file)?,
    };
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
pub fn format_of(path: &Path, bytes: &[u8]) -> Result<Format, Refusal> {
    if bytes.starts_with(b"\x7fELF") {
        return Ok(Format::Elf);
    }
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    match ext.as_str() {
        "hex" | "ihex" | "ihx" => Ok(Format::Hex),
        "bin" => Ok(Format::Bin),
        "elf" => Err(Refusal::new("must be an ELF, .hex or .bin file", "named .elf but not an ELF file")),
        _ if bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b':') => Ok(Format::Hex),
        _ => Ok(Format::Bin),
    }
}

/// Sectors 0-5 as the pieces of a .hex or an ELF fill them: each byte
/// placed at most once, nothing outside FLASH_BASE..APP_END.
pub struct Canvas {
    bytes: Vec<u8>,
    placed: Vec<bool>,
    lowest: u32,
    end: u32,
}

impl Canvas {
    pub fn new() -> Canvas {
        let n = IMAGE_MAX_BYTES as usize;
        Canvas { bytes: vec![0xFF; n], placed: vec![false; n], lowest: APP_END, end: FLASH_BASE }
    }

    /// `what` names the piece in a refusal ("line 12", "segment 2").
    pub fn place(&mut self, address: u32, data: &[u8], what: &str) -> Result<(), Refusal> {
        let end = u64::from(address) + data.len() as u64;
        if address < FLASH_BASE || address >= super::sector_start(SECTOR_KIB.len()) {
            let rule = format!("must lie in flash, 0x{FLASH_BASE:08x}..0x{APP_END:08x} (sectors 0-5)");
            return Err(Refusal::new(rule, format!("{what} at 0x{address:08x}")));
        }
        if end > u64::from(APP_END) {
            let rule = format!(
                "must fit in sectors 0-5, 0x{FLASH_BASE:08x}..0x{APP_END:08x}, 1..={IMAGE_MAX_BYTES} bytes (sectors 6-7 keep the saved settings and cam tables)"
            );
            return Err(Refusal::new(
                rule,
                format!("{what} reaches 0x{end:08x}, {} bytes", end - u64::from(FLASH_BASE)),
            ));
        }
        let at = (address - FLASH_BASE) as usize;
        if let Some(i) = self.placed[at..at + data.len()].iter().position(|&p| p) {
            let twice = address as usize + i;
            return Err(Refusal::new("must give each byte once", format!("{what} writes 0x{twice:08x} again")));
        }
        self.bytes[at..at + data.len()].copy_from_slice(data);
        self.placed[at..at + data.len()].iter_mut().for_each(|p| *p = true);
        if !data.is_empty() {
            self.lowest = self.lowest.min(address);
            self.end = self.end.max(end as u32);
        }
        Ok(())
    }

    /// The image from FLASH_BASE to its last byte.
    pub fn finish(mut self) -> Result<(u32, Vec<u8>), Refusal> {
        if self.end == FLASH_BASE {
            return Err(Refusal::new(format!("must not be empty (1..={IMAGE_MAX_BYTES} bytes)"), "no data"));
        }
        if self.lowest != FLASH_BASE {
            let rule = format!("must start at 0x{FLASH_BASE:08x}, with the vector table (sector 0)");
            return Err(Refusal::new(rule, format!("starts at 0x{:08x}", self.lowest)));
        }
        self.bytes.truncate((self.end - FLASH_BASE) as usize);
        Ok((FLASH_BASE, self.bytes))
    }
}

impl Default for Canvas {
    fn default() -> Canvas {
        Canvas::new()
    }
}
