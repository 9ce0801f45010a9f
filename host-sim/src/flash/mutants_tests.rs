//! A release image damaged on its way: cut short anywhere, grown by a few
//! bytes, a byte of its vector table or anywhere else changed. Every such
//! mutant is refused, whichever way it comes (.bin or .hex), and the
//! firmware's own boot check (`polyturn_firmware::seal::verify`, on the
//! model of the CRC unit) refuses the same flash contents.
//!
//! The image is the real one when `cargo fw` has built it (made as
//! `polyturn image` makes it), else a synthetic one from the test kit.

use super::image::{from_bytes, Format};
use super::{hex, Image, VECTOR_TABLE_BYTES};
use polyturn_bench::flash::testkit::good;
use polyturn_firmware::regs::Bus;
use polyturn_firmware::seal::{self, CRC_BASE, FLASH_BASE, RCC_AHB1ENR, SEAL_BYTES};
use polyturn_stm32_model::chip::crc::Crc;
use proptest::prelude::*;
use std::path::PathBuf;
use std::sync::OnceLock;

fn built_elf() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")));
    target.join("thumbv7em-none-eabihf/fw/polyturn-firmware")
}

/// The release image's bytes (the `.bin` `polyturn image` writes).
fn release() -> &'static Image {
    static IMAGE: OnceLock<Image> = OnceLock::new();
    IMAGE.get_or_init(|| match std::fs::read(built_elf()) {
        Ok(elf) => from_bytes(&elf, Format::Elf, false).expect("the built firmware is an image"),
        Err(_) => from_bytes(&good(70_001), Format::Bin, false).expect("the test kit's image"),
    })
}

#[derive(Clone, Debug)]
enum Mutant {
    Cut(usize),
    Append(Vec<u8>),
    Flip { at: usize, xor: u8 },
}

fn mutant() -> impl Strategy<Value = Mutant> {
    let len = release().bytes.len();
    prop_oneof![
        (1..len).prop_map(Mutant::Cut),
        prop::collection::vec(any::<u8>(), 1..64).prop_map(Mutant::Append),
        (0..VECTOR_TABLE_BYTES as usize, 1..=255u8).prop_map(|(at, xor)| Mutant::Flip { at, xor }),
        (0..len, 1..=255u8).prop_map(|(at, xor)| Mutant::Flip { at, xor }),
    ]
}

fn apply(m: &Mutant) -> Vec<u8> {
    let mut b = release().bytes.clone();
    match m {
        Mutant::Cut(keep) => b.truncate(*keep),
        Mutant::Append(more) => b.extend_from_slice(more),
        Mutant::Flip { at, xor } => b[*at] ^= xor,
    }
    b
}

#[test]
fn every_mutant_of_the_release_image_is_refused_as_bin_and_as_hex() {
    let cfg = ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() };
    proptest!(cfg, |(m in mutant())| {
        let bytes = apply(&m);
        let as_bin = from_bytes(&bytes, Format::Bin, false);
        prop_assert!(as_bin.is_err(), "{m:?} passed as .bin: {:?}", as_bin.map(|i| i.version));
        // the .hex of the damaged bytes, well-formed as a file
        if let Ok(text) = hex::write(&Image { bytes, ..release().clone() }) {
            prop_assert!(from_bytes(text.as_bytes(), Format::Hex, false).is_err(), "{m:?} passed as .hex");
        }
    });
}

/// The flash after writing `bytes` over erased sectors, as the firmware's
/// boot check reads it, with the model of the CRC unit.
struct Board<'a> {
    flash: &'a [u8],
    crc: Crc,
    ahb1enr: u32,
}

impl Bus for Board<'_> {
    fn write(&mut self, addr: u32, value: u32) {
        match addr {
            RCC_AHB1ENR => self.ahb1enr = value,
            _ => self.crc.write(addr - CRC_BASE, value, u32::MAX),
        }
    }
    fn read(&mut self, addr: u32) -> u32 {
        match addr {
            RCC_AHB1ENR => self.ahb1enr,
            a if a >= CRC_BASE => self.crc.read(a - CRC_BASE),
            a => {
                let b = |i: u32| self.flash.get((a - FLASH_BASE + i) as usize).copied().unwrap_or(0xFF);
                u32::from_le_bytes([b(0), b(1), b(2), b(3)])
            }
        }
    }
    fn delay(&mut self, _: u32) {}
}

/// The firmware's verdict on `bytes` in flash; its link puts the image's
/// end where the whole image's seal begins.
fn boots(bytes: &[u8]) -> Result<(), seal::Damage> {
    let end = FLASH_BASE + release().bytes.len() as u32 - SEAL_BYTES;
    seal::verify(&mut Board { flash: bytes, crc: Crc::default(), ahb1enr: 0 }, end)
}

#[test]
fn the_board_refuses_to_run_every_cut_or_changed_mutant() {
    assert_eq!(boots(&release().bytes), Ok(()));
    let cfg = ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() };
    proptest!(cfg, |(m in mutant())| {
        let verdict = boots(&apply(&m));
        match m {
            // bytes past the seal lie past the image: never run, harmless
            // to the board (the host refuses them: above)
            Mutant::Append(_) => prop_assert_eq!(verdict, Ok(())),
            _ => prop_assert!(verdict.is_err(), "{m:?} would run"),
        }
    });
}

#[test]
fn the_whole_release_image_passes_as_bin_and_as_hex() {
    let image = release();
    assert_eq!(from_bytes(&image.bytes, Format::Bin, false).as_ref(), Ok(image));
    let text = hex::write(image).unwrap();
    assert_eq!(from_bytes(text.as_bytes(), Format::Hex, false).as_ref(), Ok(image));
}

/// The firmware finds its seal at its link's end of `.data`'s load image
/// (`app/seal.rs`: `__sidata + (__edata - __sdata)`); `polyturn image`
/// puts it after the ELF's last loaded byte. They must be one place (the
/// emulator's boot of the real image checks the same from the other side).
#[test]
fn the_seal_lies_where_the_firmwares_link_says_its_image_ends() {
    use object::{Object, ObjectSymbol};
    let Ok(file) = std::fs::read(built_elf()) else {
        eprintln!("no firmware built ({}): `cargo fw` first", built_elf().display());
        return;
    };
    let elf = object::File::parse(&*file).unwrap();
    let sym = |name: &str| elf.symbols().find(|s| s.name() == Ok(name)).map(|s| s.address() as u32).unwrap();
    let end = sym("__sidata") + (sym("__edata") - sym("__sdata"));
    let image = from_bytes(&file, Format::Elf, false).unwrap();
    assert_eq!(FLASH_BASE + image.bytes.len() as u32 - SEAL_BYTES, end);
}

/// The CRC the host seals with is the CRC unit's (RM0383 §4.3) as the
/// model reads it, word for word; and the value ST's CRC examples give for
/// one word, 0x12345678 → 0xDF8A8A2B.
#[test]
fn the_host_seals_with_the_crc_units_algorithm() {
    use polyturn_stm32_model::chip::crc::of_words;
    assert_eq!(polyturn_firmware::seal::crc_of_words([0x1234_5678]), 0xDF8A_8A2B);
    assert_eq!(of_words([0x1234_5678]), 0xDF8A_8A2B);
    proptest!(ProptestConfig::with_cases(256), |(words in proptest::collection::vec(any::<u32>(), 0..64))| {
        prop_assert_eq!(polyturn_firmware::seal::crc_of_words(words.iter().copied()), of_words(words.iter().copied()));
    });
}
