//! The image checks: what is flashed, and every way a file is refused.

use super::image::{format_of, from_bytes, load, read_bounded, Format, FILE_MAX_BYTES};
use super::Refusal;
use super::{hex, FLASH_BASE};
use polyturn_bench::flash::testkit::{elf, elf_for, good, image_with, record, unsealed, RESET, SP};
use std::path::Path;

fn refused(bytes: &[u8], format: Format, any_image: bool) -> Refusal {
    from_bytes(bytes, format, any_image).expect_err("refused")
}

/// A .hex of `pieces` (address, bytes), records of 16 bytes.
fn hex_of(pieces: &[(u32, &[u8])]) -> String {
    let mut lines = Vec::new();
    for (address, bytes) in pieces {
        lines.push(record(4, 0, &((address >> 16) as u16).to_be_bytes()));
        for (i, chunk) in bytes.chunks(16).enumerate() {
            lines.push(record(0, (*address as u16).wrapping_add(16 * i as u16), chunk));
        }
    }
    lines.push(":00000001FF".into());
    lines.join("\n")
}

#[test]
fn a_good_image_loads_from_bin_hex_and_elf_alike() {
    let bytes = good(3000);
    let from_bin = from_bytes(&bytes, Format::Bin, false).unwrap();
    assert_eq!((from_bin.base, from_bin.version.as_deref()), (FLASH_BASE, Some("0.1.0")));
    assert_eq!(from_bin.bytes, bytes);
    assert_eq!(from_bin.sha256.len(), 64);
    let from_hex = from_bytes(hex_of(&[(FLASH_BASE, &bytes)]).as_bytes(), Format::Hex, false).unwrap();
    // .data: run address in RAM, stored in flash after the rest (LMA); the
    // ELF's image is sealed as the .bin is
    let raw = unsealed(3000);
    let file = elf(&[(FLASH_BASE, FLASH_BASE, &raw[..1000], 0), (FLASH_BASE + 1000, 0x2000_0000, &raw[1000..], 64)]);
    let from_elf = from_bytes(&file, Format::Elf, false).unwrap();
    assert_eq!((&from_hex, &from_elf), (&from_bin, &from_bin));
    let mut other = raw.clone();
    other[2999] ^= 1;
    let other = from_bytes(&elf(&[(FLASH_BASE, FLASH_BASE, &other, 0)]), Format::Elf, false).unwrap();
    assert_ne!(other.sha256, from_bin.sha256);
}

#[test]
fn an_unmarked_image_is_neither_sealed_nor_asked_for_a_seal() {
    let raw = image_with(4096, SP, RESET, b"");
    let from_elf = from_bytes(&elf(&[(FLASH_BASE, FLASH_BASE, &raw, 0)]), Format::Elf, true).unwrap();
    assert_eq!((from_elf.bytes, from_elf.version), (raw.clone(), None));
    assert!(from_bytes(&raw, Format::Bin, true).is_ok());
    // marked, it must be sealed, --any-image or not
    for any in [false, true] {
        let r = refused(&unsealed(4096), Format::Bin, any);
        assert!(r.rule.starts_with("must end with the seal `polyturn image` writes"), "{r:?}");
    }
}

#[test]
fn an_elf_that_fills_sector_5_has_no_room_for_its_seal() {
    let full = unsealed(256 * 1024);
    let r = refused(&elf(&[(FLASH_BASE, FLASH_BASE, &full, 0)]), Format::Elf, false);
    assert_eq!(
        (r.rule.as_str(), r.found.as_str()),
        ("must fit in sectors 0-5 with its seal, 1..=262144 bytes", "262156 bytes from 0x08000000")
    );
    let fits = unsealed(256 * 1024 - 12);
    assert_eq!(
        from_bytes(&elf(&[(FLASH_BASE, FLASH_BASE, &fits, 0)]), Format::Elf, false).unwrap().bytes.len(),
        262_144
    );
}

#[test]
fn gaps_are_erased_flash_and_bss_is_not_flashed() {
    let bytes = unsealed(1024);
    let file =
        elf(&[(FLASH_BASE, FLASH_BASE, &bytes[..768], 0), (FLASH_BASE + 900, FLASH_BASE + 900, &bytes[900..], 0)]);
    let image = from_bytes(&file, Format::Elf, false).unwrap();
    assert_eq!((&image.bytes[..768], &image.bytes[900..1024]), (&bytes[..768], &bytes[900..]));
    assert!(image.bytes[768..900].iter().all(|&b| b == 0xFF));
    assert_eq!(image.bytes.len(), 1024 + 12, "and its seal");
}

#[test]
fn the_hex_written_loads_back_to_the_same_bytes() {
    for len in [8 + 0x200 + 40, 65_536 + 17, 256 * 1024 - 12] {
        let image = from_bytes(&good(len), Format::Bin, false).unwrap();
        let text = hex::write(&image).unwrap();
        assert!(text.ends_with(":00000001FF\n") && text.starts_with(":020000040800F2\n"), "{len}");
        assert_eq!(from_bytes(text.as_bytes(), Format::Hex, false).unwrap(), image, "{len}");
    }
}

#[test]
fn a_sealed_hex_missing_a_record_is_said_to_miss_one() {
    let bytes = good(3000);
    let text = hex_of(&[(FLASH_BASE, &bytes)]);
    // the record for 0x08000100..0x08000110 dropped
    let gone: Vec<&str> = text.lines().filter(|l| !l.starts_with(":10010000")).collect();
    assert_eq!(gone.len() + 1, text.lines().count());
    let e = refused(gone.join("\n").as_bytes(), Format::Hex, false);
    assert_eq!(e.found, "no record gives 0x08000100..0x08000110 (16 bytes): a record is missing");
    // an unmarked program's gaps are erased flash, as before
    let raw = image_with(1024, SP, RESET, b"");
    let other = hex_of(&[(FLASH_BASE, &raw[..512]), (FLASH_BASE + 640, &raw[640..])]);
    assert!(from_bytes(other.as_bytes(), Format::Hex, true).is_ok());
}

#[test]
fn sizes_and_addresses_outside_sectors_0_to_5_are_refused_with_the_range() {
    let r = refused(&[], Format::Bin, true);
    assert!(r.rule.contains("must not be empty (1..=262144 bytes)"), "{r:?}");
    let r = refused(&unsealed(256 * 1024 + 4), Format::Bin, false);
    assert!(r.rule.contains("1..=262144 bytes") && r.rule.contains("sectors 6-7"), "{r:?}");
    assert_eq!(r.found, "the data reaches 0x08040004, 262148 bytes");
    let bytes = good(1024);
    let r = refused(hex_of(&[(FLASH_BASE, &bytes), (0x0804_0000, &[1, 2])]).as_bytes(), Format::Hex, false);
    assert!(r.found.starts_with("line ") && r.found.contains("reaches 0x08040002"), "{r:?}");
    let r = refused(hex_of(&[(FLASH_BASE + 0x4000, &bytes)]).as_bytes(), Format::Hex, false);
    assert_eq!((r.rule.contains("must start at 0x08000000"), r.found.as_str()), (true, "starts at 0x08004000"));
    let r = refused(
        &elf(&[(FLASH_BASE, FLASH_BASE, &bytes, 0), (0x2000_0000, 0x2000_0000, &[1; 4], 0)]),
        Format::Elf,
        false,
    );
    assert!(r.rule.contains("must lie in flash") && r.found == "segment 1 at 0x20000000", "{r:?}");
    let r = refused(&elf(&[(0xFFFF_FFF0, 0, &[0; 64], 0)]), Format::Elf, true);
    assert_eq!(r.found, "segment 0 at 0xfffffff0");
    let r = refused(&elf(&[(FLASH_BASE, FLASH_BASE, &bytes, 0), (0x0807_FFF0, 0, &[0; 64], 0)]), Format::Elf, true);
    assert_eq!(r.found, "segment 1 reaches 0x08080030, 524336 bytes");
}

#[test]
fn a_vector_table_that_cannot_start_is_refused() {
    let cases: [(Vec<u8>, &str); 7] = [
        (unsealed(6), "6 bytes"),
        (image_with(4096, 0x2003_0000, RESET, b""), "stack pointer 0x20030000"),
        (image_with(4096, 0x2000_0000, RESET, b""), "stack pointer 0x20000000"),
        (image_with(4096, 0x2001_fffe, RESET, b""), "stack pointer 0x2001fffe"),
        (image_with(4096, 0x0800_1000, RESET, b""), "stack pointer 0x08001000"),
        (image_with(4096, SP, RESET - 1, b""), "reset address 0x08000198, even"),
        (image_with(4096, SP, 0x0810_0001, b""), "reset address 0x08100001"),
    ];
    for (bytes, found) in cases {
        let r = refused(&bytes, Format::Bin, true);
        assert_eq!(r.found, found, "{r:?}");
    }
    // shorter than its vector table: said to be cut short, not a reversed
    // range for the reset address
    let r = refused(&image_with(200, SP, RESET, b""), Format::Bin, true);
    assert_eq!(
        (r.found.as_str(), r.rule.contains("vector table (408 bytes)")),
        ("200 bytes: cut short", true),
        "{r:?}"
    );
    assert!(from_bytes(&image_with(4096, SP, FLASH_BASE + 4095, b""), Format::Bin, true).is_ok());
    assert!(refused(&image_with(4096, SP, FLASH_BASE + 4097, b""), Format::Bin, true).rule.contains("0x08001000"));
}

#[test]
fn a_vector_past_the_files_end_is_told_as_an_image_cut_short() {
    // handlers in the second half of a 4 KiB image, the file cut in half
    // (its marker, at the end, gone with it)
    let late = FLASH_BASE + 3001;
    let mut bytes = image_with(4096, SP, RESET, b"");
    bytes[12..16].copy_from_slice(&late.to_le_bytes());
    bytes.truncate(2048);
    let r = refused(&bytes, Format::Bin, false);
    assert!(r.rule.contains("HardFault"), "{r:?}");
    assert_eq!(
        r.found,
        "HardFault address 0x08000bb9 (vector table word 3), past the file's end at 0x08000800: cut short"
    );
    let r = refused(&image_with(2048, SP, late, b""), Format::Bin, false);
    assert_eq!(r.found, "reset address 0x08000bb9, past the file's end at 0x08000800: cut short");
}

#[test]
fn the_marker_names_the_chip_and_only_any_image_lets_none_through() {
    let other = image_with(4096, SP, RESET, b"polyturn-image:stm32f103c8:0.1.0\0");
    for any in [false, true] {
        let r = refused(&other, Format::Bin, any);
        assert_eq!(
            (r.rule.as_str(), r.found.as_str()),
            ("must be a polyturn image for the stm32f411ce", "made for the stm32f103c8")
        );
    }
    let none = image_with(4096, SP, RESET, b"");
    let r = refused(&none, Format::Bin, false);
    assert!(
        r.rule.contains("--any-image")
            && r.found == "no polyturn-image marker: another program, or a polyturn image cut short",
        "{r:?}"
    );
    assert_eq!(from_bytes(&none, Format::Bin, true).unwrap().version, None);
    let unended = image_with(4096, SP, RESET, &[b"polyturn-image:stm32f411ce:".as_slice(), &[b'1'; 100]].concat());
    assert!(refused(&unended, Format::Bin, true).found.starts_with("a malformed marker at offset 0x200"));
    let mut two = good(4096);
    two[0x400..0x400 + 33].copy_from_slice(b"polyturn-image:stm32f411ce:0.2.0\0");
    assert_eq!(refused(&two, Format::Bin, false).found, "markers for stm32f411ce:0.1.0 and stm32f411ce:0.2.0");
}

#[test]
fn malformed_or_overlapping_hex_is_refused_naming_the_line() {
    let bytes = unsealed(64);
    let ok = hex_of(&[(FLASH_BASE, &bytes)]);
    let bad_sum = ok.replacen(":10000000", ":10000001", 1);
    let cases = [
        (bad_sum, "line 2: checksum "),
        (ok.replace(":00000001FF", ""), "no end-of-file record (cut short?)"),
        (format!("{ok}\n{}", record(0, 0x40, &[0])), "line 7 comes after the end-of-file record"),
        (ok.replacen(":020000040800F2", ":020000020000FC", 1), "line 1 is an 8086 segment record"),
        (ok.replacen(":10", ":1G", 1), "line 2: invalid characters"),
        (
            ok.replacen(":020000040800F2", &format!("{}\n{}", record(4, 0, &[8, 0]), record(0, 0xFFF8, &[0; 16])), 1),
            "crosses a 64 KiB boundary",
        ),
        ("\u{feff}garbage".to_string(), "line 1: missing start code"),
    ];
    for (text, found) in cases {
        let r = refused(text.as_bytes(), Format::Hex, false);
        assert!(r.found.contains(found), "{found}: {r:?}");
    }
    assert!(refused(&[0xC3, 0x28], Format::Hex, false).found == "not text");
    let twice = hex_of(&[(FLASH_BASE, &bytes), (FLASH_BASE + 0x10, &[1, 2, 3])]);
    let r = refused(twice.as_bytes(), Format::Hex, false);
    assert_eq!((r.rule.as_str(), r.found.as_str()), ("must give each byte once", "line 7 writes 0x08000010 again"));
}

#[test]
fn elf_files_for_other_machines_or_broken_are_refused() {
    let bytes = good(256);
    let mut sixty_four = elf(&[(FLASH_BASE, FLASH_BASE, &bytes, 0)]);
    sixty_four[4] = 2;
    let mut big = elf(&[(FLASH_BASE, FLASH_BASE, &bytes, 0)]);
    big[5] = 2;
    let mut cut = elf(&[(FLASH_BASE, FLASH_BASE, &bytes, 0)]);
    cut.truncate(200);
    let cases = [
        (sixty_four, "a 64-bit ELF"),
        (big, "a big-endian ELF"),
        (elf_for(62, &[(FLASH_BASE, FLASH_BASE, &bytes, 0)]), "an ELF for machine 62"),
        (cut, "cut short: segment 0 reaches past its end (200 bytes)"),
        (b"\x7fELF".to_vec(), ""),
    ];
    for (file, found) in cases {
        let r = refused(&file, Format::Elf, true);
        assert!(r.rule.contains("32-bit little-endian ARM ELF") && r.found.contains(found), "{r:?}");
    }
}

#[test]
fn files_are_read_bounded_and_recognised() {
    let r = read_bounded(Path::new("/dev/zero")).unwrap_err();
    assert_eq!(r.found, "not a regular file");
    assert!(read_bounded(Path::new("/nonexistent/x.bin")).is_err() && read_bounded(Path::new("/tmp")).is_err());
    let dir = std::env::temp_dir().join(format!("polyturn-flash-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let huge = dir.join("huge.bin");
    std::fs::File::create(&huge).unwrap().set_len(FILE_MAX_BYTES + 1).unwrap();
    assert!(read_bounded(&huge).unwrap_err().rule.contains("at most 16777216 bytes"));
    assert!(load(&huge, true).is_err());
    let p = |n: &str| dir.join(n);
    assert_eq!(format_of(&p("a.HEX"), b"\x00"), Ok(Format::Hex));
    // HEX text named .bin is told, not read as a raw image; a raw image
    // whose first byte is ':' still is one
    assert!(format_of(&p("a.bin"), b":1000\r\n").unwrap_err().found.contains("Intel HEX text"));
    assert_eq!(format_of(&p("a.bin"), b":\x00\x01\x20"), Ok(Format::Bin));
    assert_eq!(format_of(&p("a"), b"\r\n:1000"), Ok(Format::Hex));
    assert_eq!(format_of(&p("a.hex"), b"\x7fELF"), Ok(Format::Elf));
    assert_eq!(format_of(&p("firmware"), &good(64)), Ok(Format::Bin));
    assert!(format_of(&p("a.elf"), b":10").is_err());
    std::fs::write(p("fw.bin"), good(4096)).unwrap();
    assert_eq!(load(&p("fw.bin"), false).unwrap().bytes, good(4096));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_relocatable_or_shared_elf_is_refused_as_not_linked() {
    let bytes = good(4096);
    for (e_type, found) in
        [(1u8, "a relocatable object (ET_REL)"), (3, "a shared object (ET_DYN)"), (4, "a core dump (ET_CORE)")]
    {
        let mut file = elf(&[(FLASH_BASE, FLASH_BASE, &bytes, 0)]);
        file[16] = e_type;
        let r = refused(&file, Format::Elf, true);
        assert_eq!(
            (r.rule.as_str(), r.found.as_str()),
            ("must be a linked executable ELF (ET_EXEC), as `cargo fw` builds it", found)
        );
    }
}

#[test]
fn a_reset_address_inside_the_vector_table_is_refused() {
    // 0x198: the F411's 16 system and 86 interrupt vectors
    for reset in [FLASH_BASE + 9, FLASH_BASE + 0x41, FLASH_BASE + 0x197] {
        let r = refused(&image_with(4096, SP, reset, b""), Format::Bin, true);
        assert_eq!(r.found, format!("reset address 0x{reset:08x}, inside the vector table"));
        assert!(r.rule.contains("0x08000198..0x08001000"), "{r:?}");
    }
    assert!(from_bytes(&image_with(4096, SP, FLASH_BASE + 0x199, b""), Format::Bin, true).is_ok());
}

#[test]
fn a_hex_start_address_must_be_the_reset_vector_and_lines_must_be_bare_records() {
    // 1024 bytes with the seal: 64 records
    let bytes = good(1012);
    let ok = hex_of(&[(FLASH_BASE, &bytes)]);
    let eof = ":00000001FF";
    let start = |a: u32| record(5, 0, &a.to_be_bytes());
    // objcopy's start address (the ELF entry, the reset handler) is taken
    assert!(from_bytes(ok.replace(eof, &format!("{}\n{eof}", start(RESET))).as_bytes(), Format::Hex, false).is_ok());
    let cases = [
        (
            ok.replace(eof, &format!("{}\n{eof}", start(FLASH_BASE + 0x401))),
            "line 66: start address 0x08000401, not the vector table's reset address 0x08000199",
        ),
        (ok.replace(eof, &format!("{}\n{}\n{eof}", start(RESET), start(RESET))), "line 67: a second start address"),
        (ok.replacen("\n", "\n\n", 1), "line 2 is blank"),
        (format!("{ok}\n\n"), "line 67 is blank"),
        (ok.replacen("\n:10", "\n :10", 1), "line 2 has spaces or tabs around its record"),
        (ok.replacen("\n:10", "\t\n:10", 1), "line 1 has spaces or tabs around its record"),
    ];
    for (text, found) in cases {
        let r = refused(text.as_bytes(), Format::Hex, false);
        assert_eq!(r.found, found, "{r:?}");
    }
}

#[test]
fn an_unmarked_image_needs_its_always_enabled_handlers_in_the_image() {
    let with = |word: usize, v: u32| {
        let mut b = image_with(4096, SP, RESET, b"");
        b[word * 4..word * 4 + 4].copy_from_slice(&v.to_le_bytes());
        from_bytes(&b, Format::Bin, true)
    };
    // a table shifted or cut so that its words are garbage: the reset
    // vector alone still looked right
    let r = with(2, 0x4142_4344).expect_err("garbage NMI");
    assert_eq!(r.found, "NMI address 0x41424344 (vector table word 2)", "{r:?}");
    assert!(r.rule.contains("0x08000198..0x08001000") && !r.rule.contains("or 0"), "{r:?}");
    assert_eq!(with(3, 0).expect_err("no HardFault").found, "HardFault address 0x00000000 (vector table word 3)");
    assert!(with(3, RESET & !1).is_err(), "an even HardFault is ARM code, which the M4 cannot run");
    // a handler the program never enables may be 0, not garbage
    assert!(with(15, 0).is_ok());
    let r = with(15, FLASH_BASE + 5001).expect_err("SysTick past the end");
    assert!(r.rule.ends_with("or 0 (never enabled)") && r.found.starts_with("SysTick"), "{r:?}");
    // reserved words are not read
    assert!(with(7, 0xDEAD_BEEF).is_ok());
}

/// The checksum refusal names the byte the file holds as its checksum, and
/// the one its record's bytes make.
#[test]
fn a_bad_hex_checksum_names_the_files_byte_and_the_records_sum() {
    let ok = hex_of(&[(FLASH_BASE, &unsealed(16))]);
    let line2 = ok.lines().nth(1).unwrap();
    let right = &line2[line2.len() - 2..];
    let wrong = if right == "AB" { "AC" } else { "AB" };
    let bad = ok.replacen(line2, &format!("{}{wrong}", &line2[..line2.len() - 2]), 1);
    let r = refused(bad.as_bytes(), Format::Hex, false);
    assert!(
        r.found.ends_with(&format!("line 2: checksum {wrong} does not match the record, whose bytes make {right}")),
        "{r:?}"
    );
}

/// An image cut in half whose HardFault handler lay in the half cut off:
/// told by its seal as cut short, not by the vector its missing bytes
/// broke.
#[test]
fn an_image_cut_short_is_told_so_before_its_vectors() {
    let mut raw = unsealed(4096);
    raw[12..16].copy_from_slice(&(FLASH_BASE + 3001).to_le_bytes()); // HardFault
    let whole = {
        let mut b = raw.clone();
        super::seal::seal(&mut b);
        b
    };
    assert!(from_bytes(&whole, Format::Bin, false).is_ok());
    let r = refused(&whole[..2048], Format::Bin, false);
    assert_eq!(r.found, "no seal at its end, 2048 bytes (cut short, or not made by `polyturn image`)");
}
