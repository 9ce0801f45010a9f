//! The firmware image: what is flashed (the release image `polyturn image`
//! makes from the ELF, sealed), symbols, the vector table and the addresses of
//! the instructions the harness treats specially, all read from the ELF on
//! every run (nothing about the code is typed in here).

use object::{Object, ObjectSection, ObjectSegment, ObjectSymbol, SymbolKind};
use polyturn_host::flash::image::Format;
use std::collections::BTreeMap;
use std::path::Path;

pub use crate::disasm::Insns;

pub use polyturn_stm32_model::addr::{FLASH_BASE, FLASH_SIZE};

pub struct Image {
    /// (load address, bytes) of what is flashed: the release image as
    /// `polyturn image` makes it from the ELF (every PT_LOAD segment's file
    /// bytes at its LMA, so .data's initial values too, then the seal)
    pub segments: Vec<(u32, Vec<u8>)>,
    /// where the release image's seal lies (`polyturn_firmware::seal`); none
    /// for a bare benchmark image (`load_bare`)
    pub seal_at: Option<u32>,
    pub symbols: BTreeMap<String, u32>,
    funcs: Vec<(u32, u32, String)>,
    pub vectors: Vec<u32>,
    pub insns: Insns,
    /// every instruction, as the cycle clock times them (`cycles`)
    pub program: std::rc::Rc<crate::cycles::program::Program>,
    /// (address it runs at, address it is loaded at, length) of each segment
    /// whose two differ (`.data`, and the code memory.x puts in SRAM)
    #[cfg_attr(not(test), allow(dead_code))]
    pub moved: Vec<(u32, u32, u32)>,
}

/// Why an image cannot run, in one line.
pub fn load(path: &Path) -> Result<Image, String> {
    load_as(path, true)
}

/// A bare-metal image that is no polyturn image (`--bench`): its PT_LOAD
/// segments' file bytes at their load addresses, unsealed.
pub fn load_bare(path: &Path) -> Result<Image, String> {
    load_as(path, false)
}

fn load_as(path: &Path, polyturn: bool) -> Result<Image, String> {
    let data = std::fs::read(path).map_err(|e| format!("cannot read the image '{}': {e}", path.display()))?;
    let elf = object::File::parse(&*data).map_err(|e| format!("'{}' is not an ELF: {e}", path.display()))?;
    if elf.architecture() != object::Architecture::Arm {
        return Err(format!(
            "'{}' is an ELF for {:?}, not the STM32F411's Cortex-M4",
            path.display(),
            elf.architecture()
        ));
    }
    let (mut segments, mut moved, mut seal_at) = (Vec::new(), Vec::new(), None);
    for seg in elf.segments() {
        let bytes = seg.data().map_err(|e| e.to_string())?;
        let (vma, lma) = (seg.address() as u32, load_address(&elf, &seg));
        if !bytes.is_empty() && vma != lma {
            moved.push((vma, lma, bytes.len() as u32));
        }
        if !bytes.is_empty() && !polyturn {
            segments.push((lma, bytes.to_vec()));
        }
    }
    if polyturn {
        let release = polyturn_host::flash::image::from_bytes(&data, Format::Elf, false)
            .map_err(|r| format!("'{}' is no polyturn image: {} ({})", path.display(), r.rule, r.found))?;
        seal_at = Some(FLASH_BASE + release.bytes.len() as u32 - polyturn_firmware::seal::SEAL_BYTES);
        segments.push((release.base, release.bytes));
    }
    let (mut symbols, mut funcs) = (BTreeMap::new(), Vec::new());
    for s in elf.symbols() {
        let Ok(name) = s.name() else { continue };
        if name.is_empty() || name.starts_with('$') {
            continue;
        }
        let mut addr = s.address() as u32;
        if s.kind() == SymbolKind::Text {
            addr &= !1;
            funcs.push((addr, s.size() as u32, name.to_string()));
        }
        symbols.entry(name.to_string()).or_insert(addr);
    }
    funcs.sort();
    let vt = elf.section_by_name(".vector_table").ok_or("the ELF has no .vector_table: not a cortex-m-rt image")?;
    let raw = vt.data().map_err(|e| e.to_string())?;
    let vectors = raw.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect();
    let listing = crate::disasm::text(path)?;
    let insns = crate::disasm::scan(&listing);
    let program = crate::cycles::program::Program::parse(&listing);
    if let Some((addr, why)) = program.unknown().first() {
        return Err(format!("the cycle clock cannot time the instruction at {addr:#010x}: {why}"));
    }
    Ok(Image { segments, seal_at, symbols, funcs, vectors, insns, program: std::rc::Rc::new(program), moved })
}

/// A segment's physical (load) address: `object` gives the virtual one, so take
/// p_paddr from the program header.
fn load_address(elf: &object::File, seg: &object::Segment) -> u32 {
    use object::read::elf::ProgramHeader;
    if let object::File::Elf32(f) = elf {
        let (off, _) = seg.file_range();
        for ph in f.elf_program_headers() {
            if ph.p_offset(f.endian()) as u64 == off && ph.p_filesz(f.endian()) > 0 {
                return ph.p_paddr(f.endian());
            }
        }
    }
    seg.address() as u32
}

/// Seals `flash` (from FLASH_BASE) again for its bytes before `seal_at`, as
/// `polyturn image` seals (the CRC unit's CRC of the words, RM0383 §4).
pub fn reseal(flash: &mut [u8], seal_at: u32) {
    let at = (seal_at - FLASH_BASE) as usize;
    let crc = polyturn_host::flash::seal::crc_of(&flash[..at]);
    flash[at + 8..at + 12].copy_from_slice(&crc.to_le_bytes());
}

impl Image {
    /// Where the bytes that run at `addr` are loaded (the same address but
    /// for a moved segment's).
    #[cfg(test)]
    pub fn load_address_of(&self, addr: u32) -> u32 {
        self.moved.iter().find(|m| (m.0..m.0 + m.2).contains(&addr)).map_or(addr, |m| m.1 + (addr - m.0))
    }

    /// Whether `addr` lies inside a function symbol's extent, not in the fill
    /// the linker puts between functions (lld's 0xd4d4 halfwords, which
    /// llvm-objdump shows as code).
    #[cfg(test)]
    pub fn in_function(&self, addr: u32) -> bool {
        let i = self.funcs.partition_point(|f| f.0 <= addr);
        i > 0 && addr < self.funcs[i - 1].0 + self.funcs[i - 1].1
    }

    /// The function containing `addr` (or the nearest before it), for messages.
    pub fn func_at(&self, addr: u32) -> String {
        let a = addr & !1;
        let i = self.funcs.partition_point(|f| f.0 <= a);
        if i == 0 {
            return "?".into();
        }
        let (start, size, name) = &self.funcs[i - 1];
        if *size == 0 || a < start + size {
            name.clone()
        } else {
            format!("{name}+{:#x}", a - start)
        }
    }
}
