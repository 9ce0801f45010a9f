//! The firmware ELF as `cargo fw` links it: 32-bit, little-endian, ARM.
//! What goes to flash is every PT_LOAD segment's file bytes at its
//! physical address (LMA): `.data` runs from RAM but is stored in flash
//! after `.rodata` (AT> FLASH in cortex-m-rt's link.x), and `.bss` has no
//! file bytes. This is what `objcopy -O binary` takes.

use super::{Canvas, Refusal};
use object::elf::{FileHeader32, FileType, ELFCLASS32, ELFDATA2LSB, EM_ARM, ET_CORE, ET_DYN, ET_EXEC, ET_REL, PT_LOAD};
use object::read::elf::{FileHeader, ProgramHeader};
use object::Endianness;

const ELF_RULE: &str = "must be a 32-bit little-endian ARM ELF (the firmware as `cargo fw` builds it)";
/// An object file's segments are not placed yet (a `.o` has none; its
/// sections sit at address 0 until the linker moves them).
const EXEC_RULE: &str = "must be a linked executable ELF (ET_EXEC), as `cargo fw` builds it";

pub fn parse(file: &[u8]) -> Result<(u32, Vec<u8>), Refusal> {
    // the ident bytes first, for a plainer refusal than the parser's
    match (file.get(4), file.get(5)) {
        (Some(&c), _) if c != ELFCLASS32.0 => return Err(Refusal::new(ELF_RULE, "a 64-bit ELF")),
        (_, Some(&d)) if d != ELFDATA2LSB.0 => return Err(Refusal::new(ELF_RULE, "a big-endian ELF")),
        _ => {}
    }
    let bad = |e: object::read::Error| Refusal::new(ELF_RULE, e.to_string());
    let header = FileHeader32::<Endianness>::parse(file).map_err(bad)?;
    let endian = header.endian().map_err(bad)?;
    if header.e_machine(endian) != EM_ARM {
        return Err(Refusal::new(ELF_RULE, format!("an ELF for machine {}", header.e_machine(endian).0)));
    }
    if header.e_type(endian) != ET_EXEC {
        return Err(Refusal::new(EXEC_RULE, kind(header.e_type(endian))));
    }
    let mut canvas = Canvas::new();
    for (i, segment) in header.program_headers(endian, file).map_err(bad)?.iter().enumerate() {
        if segment.p_type(endian) != PT_LOAD || segment.p_filesz(endian) == 0 {
            continue;
        }
        let data = segment.data(endian, file).map_err(|()| {
            Refusal::new(ELF_RULE, format!("cut short: segment {i} reaches past its end ({} bytes)", file.len()))
        })?;
        canvas.place(segment.p_paddr(endian), data, &format!("segment {i}"))?;
    }
    canvas.finish()
}

/// What an ELF that is no executable is.
fn kind(e_type: FileType) -> String {
    match e_type {
        ET_REL => "a relocatable object (ET_REL)".into(),
        ET_DYN => "a shared object (ET_DYN)".into(),
        ET_CORE => "a core dump (ET_CORE)".into(),
        other => format!("an ELF of type {}", other.0),
    }
}
