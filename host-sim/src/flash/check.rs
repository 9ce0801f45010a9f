//! What an image must be before it is flashed: a Cortex-M vector table
//! that can start (PM0214 §2.3.4: word 0 the initial SP, word 1 the reset
//! handler with bit 0 set for Thumb), a polyturn marker naming this
//! chip, and the seal that says the image is whole (`seal.rs`), so that a
//! file for another board, no firmware at all, or an image cut short or
//! altered, is refused before the bootloader erases anything.

use super::{seal, Refusal};
use super::{APP_END, CHIP, FLASH_BASE, IMAGE_MAX_BYTES, MARKER, RAM_END, RAM_START, VECTOR_TABLE_BYTES};

/// A marker's chip and version are short: a longer one is no marker.
const MARKER_TEXT_MAX: usize = 80;

/// Checks an image placed at `base`; the version its marker gives (`None`
/// when `any_image` lets an image without a marker through). A polyturn
/// image must be sealed (an unmarked one has no seal to check).
pub fn image(base: u32, bytes: &[u8], any_image: bool) -> Result<Option<String>, Refusal> {
    // a marked image's seal first: an image cut short is told so, not by
    // whichever vector its missing bytes broke
    match markers(bytes)? {
        Some((chip, _)) if chip != CHIP => {
            Err(Refusal::new(format!("must be a polyturn image for the {CHIP}"), format!("made for the {chip}")))
        }
        Some((_, version)) => {
            seal::check(bytes)?;
            vectors(base, bytes)?;
            fits(base, bytes)?;
            Ok(Some(version))
        }
        None => vectors(base, bytes).and_then(|()| unmarked(any_image)),
    }
}

/// An image without a polyturn marker: taken only with `--any-image`.
fn unmarked(any_image: bool) -> Result<Option<String>, Refusal> {
    match any_image {
        true => Ok(None),
        false => Err(Refusal::new(
            format!("must be a polyturn image for the {CHIP}, marked 'polyturn-image:{CHIP}:VERSION' (--any-image writes another program)"),
            "no polyturn-image marker: another program, or a polyturn image cut short",
        )),
    }
}

/// Whether the image carries a well-formed polyturn marker (an ELF's
/// image is then sealed as `polyturn image` seals it).
pub fn marked(bytes: &[u8]) -> bool {
    matches!(markers(bytes), Ok(Some(_)))
}

/// Sealed, the image still ends in sector 5 (the seal may take it past
/// the ELF's last byte).
fn fits(base: u32, bytes: &[u8]) -> Result<(), Refusal> {
    let end = u64::from(base) + bytes.len() as u64;
    if base != FLASH_BASE || end > u64::from(APP_END) {
        let rule = format!("must fit in sectors 0-5 with its seal, 1..={IMAGE_MAX_BYTES} bytes");
        return Err(Refusal::new(rule, format!("{} bytes from 0x{base:08x}", bytes.len())));
    }
    Ok(())
}

/// The initial stack pointer in RAM and word-aligned; the reset handler
/// Thumb (odd) and inside the image, past the vector table (an address
/// in the table would run vectors as code).
fn vectors(base: u32, bytes: &[u8]) -> Result<(), Refusal> {
    let word = |i: usize| bytes.get(i..i + 4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]));
    let (Some(sp), Some(reset)) = (word(0), word(4)) else {
        let rule = "must begin with a vector table: initial stack pointer and reset address (8 bytes)";
        return Err(Refusal::new(rule, format!("{} bytes", bytes.len())));
    };
    if !(sp > RAM_START && sp <= RAM_END && sp % 4 == 0) {
        let rule = format!(
            "must begin with a vector table whose initial stack pointer is word-aligned RAM, 0x{:08x}..=0x{RAM_END:08x}",
            RAM_START + 4
        );
        return Err(Refusal::new(rule, format!("stack pointer 0x{sp:08x}")));
    }
    let (code, end) = (u64::from(base) + u64::from(VECTOR_TABLE_BYTES), u64::from(base) + bytes.len() as u64);
    if end <= code {
        let rule = format!("must hold its vector table ({VECTOR_TABLE_BYTES} bytes) and the code after it");
        return Err(Refusal::new(rule, format!("{} bytes: cut short", bytes.len())));
    }
    let rule = format!(
        "must have a reset address that is Thumb code (odd) in the image after its vector table, 0x{code:08x}..0x{end:08x}"
    );
    if reset & 1 == 0 {
        return Err(Refusal::new(rule, format!("reset address 0x{reset:08x}, even")));
    }
    let entry = u64::from(reset & !1);
    if entry >= u64::from(base) && entry < code {
        return Err(Refusal::new(rule, format!("reset address 0x{reset:08x}, inside the vector table")));
    }
    if entry < code || entry >= end {
        return Err(Refusal::new(rule, format!("reset address 0x{reset:08x}{}", past_the_end(entry, end))));
    }
    handlers(&word, code, end)
}

/// Why a handler at `entry` is not in the image ending at `end`, when
/// the image may be cut short: the address lies past the file's end but
/// inside the flash the image may take (an image cut in half keeps its
/// vectors and loses the code they point at). Else nothing to add.
fn past_the_end(entry: u64, end: u64) -> String {
    if entry >= end && entry < u64::from(APP_END) {
        format!(", past the file's end at 0x{end:08x}: cut short")
    } else {
        String::new()
    }
}

/// The system exceptions' vectors (PM0214 §2.3.4, Table 17: words 2 to
/// 15, 7 to 10 and 13 reserved). NMI and HardFault are always enabled
/// (§2.3.2), so theirs must be Thumb code in the image; the others are
/// taken only once a program enables or raises them, so 0 is allowed. An
/// image cut or shifted so that its table is garbage is refused here, where
/// the reset vector alone could still look right.
fn handlers(word: &dyn Fn(usize) -> Option<u32>, code: u64, end: u64) -> Result<(), Refusal> {
    const NAMES: [(usize, &str, bool); 9] = [
        (2, "NMI", true),
        (3, "HardFault", true),
        (4, "MemManage", false),
        (5, "BusFault", false),
        (6, "UsageFault", false),
        (11, "SVCall", false),
        (12, "DebugMonitor", false),
        (14, "PendSV", false),
        (15, "SysTick", false),
    ];
    for (n, name, always) in NAMES {
        let v = word(n * 4).unwrap_or(0);
        let inside = v & 1 == 1 && u64::from(v & !1) >= code && u64::from(v & !1) < end;
        if !(inside || (v == 0 && !always)) {
            let may = if always { "" } else { " or 0 (never enabled)" };
            let rule = format!(
                "must have a {name} handler address that is Thumb code (odd) in the image after its vector table, 0x{code:08x}..0x{end:08x}{may}"
            );
            let past = if v & 1 == 1 { past_the_end(u64::from(v & !1), end) } else { String::new() };
            return Err(Refusal::new(rule, format!("{name} address 0x{v:08x} (vector table word {n}){past}")));
        }
    }
    Ok(())
}

/// Every marker in the image: (chip, version) when there is one, or all
/// agree; refused when one is malformed or two disagree.
fn markers(bytes: &[u8]) -> Result<Option<(String, String)>, Refusal> {
    let mut found: Option<(String, String)> = None;
    let starts = bytes.windows(MARKER.len()).enumerate().filter(|(_, w)| *w == MARKER).map(|(i, _)| i);
    for at in starts {
        let rest = &bytes[at + MARKER.len()..];
        let text = rest.iter().take(MARKER_TEXT_MAX).position(|&b| b == 0).map(|n| &rest[..n]);
        let parsed = text.and_then(|t| std::str::from_utf8(t).ok()).and_then(|t| t.split_once(':')).filter(|(c, v)| {
            let ok = |s: &str, extra: &str| {
                !s.is_empty() && s.chars().all(|ch| ch.is_ascii_alphanumeric() || extra.contains(ch))
            };
            ok(c, "") && ok(v, ".-+")
        });
        let Some((chip, version)) = parsed else {
            let rule = format!("must carry a well-formed marker, 'polyturn-image:{CHIP}:VERSION' and a NUL");
            return Err(Refusal::new(rule, format!("a malformed marker at offset 0x{at:x}")));
        };
        let this = (chip.to_ascii_lowercase(), version.to_string());
        match &found {
            Some(first) if *first != this => {
                let rule = "must carry one polyturn marker";
                return Err(Refusal::new(
                    rule,
                    format!("markers for {}:{} and {}:{}", first.0, first.1, this.0, this.1),
                ));
            }
            _ => found = Some(this),
        }
    }
    Ok(found)
}
