//! `polyturn image`: a release image from the firmware ELF, as a raw
//! `.bin` (from 0x08000000) and an Intel `.hex`, checked as `polyturn
//! flash` checks what it writes; both files or neither.

use super::errors::{escaped, CliError, CliResult};
use super::output::{named, Outputs};
use super::values::out_file;
use crate::flash::image::{self, Format};
use crate::flash::{hex, last_sector, CHIP};
use crate::flash::{Image, Refusal};
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct ImageArgs {
    /// The firmware ELF (target/thumbv7em-none-eabihf/fw/polyturn-firmware after `cargo fw`)
    #[arg(value_name = "ELF")]
    pub elf: PathBuf,
    /// Write the raw image, from 0x08000000, to this file
    #[arg(long, value_name = "OUT.bin", value_parser = out_file)]
    pub bin: PathBuf,
    /// Write the image as Intel HEX to this file
    #[arg(long, value_name = "OUT.hex", value_parser = out_file)]
    pub hex: PathBuf,
    /// Take an ELF without the polyturn marker (address, size and vector table checks still apply)
    #[arg(long)]
    pub any_image: bool,
    /// Print the report as one JSON object
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: ImageArgs) -> CliResult<String> {
    let image = load("ELF", &a.elf, a.any_image, Some(Format::Elf))?;
    let text = hex::write(&image).map_err(|r| refused("ELF", &a.elf, r))?;
    let mut files = Outputs::default();
    files.reading("ELF", &a.elf);
    files.add_bytes("bin", &a.bin, image.bytes.clone())?;
    files.add("hex", &a.hex, text)?;
    let written = files.write()?;
    if a.json {
        return Ok(written.report(
            json!({
                "chip": CHIP,
                "version": image.version,
                "base": format!("0x{:08x}", image.base),
                "bytes": image.bytes.len(),
                "kib": kib(&image),
                "sectors": [0, last_sector(image.bytes.len() as u32)],
                "sha256": image.sha256,
                "bin": a.bin.display().to_string(),
                "hex": a.hex.display().to_string(),
            })
            .to_string(),
        ));
    }
    Ok(written.report(format!("{}\n{}", summary(&image), wrote(&a.bin, &a.hex))))
}

/// "wrote BIN and HEX", `-` named "stdout".
fn wrote(bin: &Path, hex: &Path) -> String {
    format!("wrote {} and {}", named(bin), named(hex))
}

/// Reads and checks an image file; a refusal names the argument:
/// `FILE must ... (got 'path': what it has)`.
pub fn load(arg: &str, path: &Path, any_image: bool, only: Option<Format>) -> CliResult<Image> {
    let bytes = image::read_bounded(path).map_err(|r| refused(arg, path, r))?;
    let format = image::format_of(path, &bytes).map_err(|r| refused(arg, path, r))?;
    if only.is_some_and(|f| f != format) {
        let r = Refusal::new("must be the firmware ELF, as `cargo fw` builds it", "not an ELF file");
        return Err(refused(arg, path, r));
    }
    image::from_bytes(&bytes, format, any_image).map_err(|r| refused(arg, path, r))
}

fn refused(arg: &str, path: &Path, r: Refusal) -> CliError {
    CliError(format!("{arg} {} (got '{}': {})", escaped(&r.rule), shown(path), escaped(&r.found)))
}

/// One line: version, size, where, sectors, SHA-256.
pub fn summary(image: &Image) -> String {
    let end = image.base as usize + image.bytes.len();
    let version = image
        .version
        .as_deref()
        .map(|v| format!("polyturn {v} for the {CHIP}"))
        .unwrap_or("an unmarked image (--any-image)".into());
    format!(
        "{version}: {} bytes ({:.1} KiB) at 0x{:08x}..0x{end:08x}, sectors 0-{}, sha256 {}",
        image.bytes.len(),
        kib(image),
        image.base,
        last_sector(image.bytes.len() as u32),
        image.sha256
    )
}

fn kib(image: &Image) -> f64 {
    image.bytes.len() as f64 / 1024.0
}

fn shown(path: &Path) -> String {
    escaped(&path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flash::FLASH_BASE;
    use polyturn_bench::flash::testkit::{elf, good, unsealed};

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("polyturn-image-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn run_line(line: &str) -> CliResult<String> {
        super::super::dispatch(&line.split(' ').map(String::from).collect::<Vec<_>>())
    }

    #[test]
    fn the_release_files_load_back_to_the_elf_image() {
        let d = dir("ok");
        std::fs::write(d.join("fw"), elf(&[(FLASH_BASE, FLASH_BASE, &unsealed(70_000), 0)])).unwrap();
        let p = |n: &str| d.join(n).display().to_string();
        let out = run_line(&format!("image {} --bin {} --hex {}", p("fw"), p("fw.bin"), p("fw.hex"))).unwrap();
        assert!(out.starts_with("polyturn 0.1.0 for the stm32f411ce: 70012 bytes (68.4 KiB) at 0x08000000..0x0801117c, sectors 0-4, sha256 "), "{out}");
        // the .bin is the ELF's bytes and the seal that `flash` and the board check
        assert_eq!(std::fs::read(p("fw.bin")).unwrap(), good(70_000));
        let from_hex = load("FILE", &d.join("fw.hex"), false, None).unwrap();
        assert_eq!(from_hex, load("FILE", &d.join("fw.bin"), false, None).unwrap());
        assert!(out.contains(&from_hex.sha256));
        let json: serde_json::Value = serde_json::from_str(
            &run_line(&format!("image {} --bin {} --hex {} --json", p("fw"), p("b"), p("h"))).unwrap(),
        )
        .unwrap();
        assert_eq!((json["bytes"].as_u64(), json["sectors"][1].as_u64()), (Some(70_012), Some(4)));
    }

    #[test]
    fn the_report_names_a_dash_stdout_as_demo_does() {
        assert_eq!(wrote(Path::new("-"), Path::new("o.hex")), "wrote stdout and o.hex");
        assert_eq!(wrote(Path::new("o.bin"), Path::new("-")), "wrote o.bin and stdout");
        assert_eq!(wrote(Path::new("a\nb"), Path::new("./-")), "wrote a\\nb and ./-");
    }

    #[test]
    fn a_refused_elf_writes_neither_file() {
        let d = dir("refused");
        let p = |n: &str| d.join(n).display().to_string();
        std::fs::write(d.join("fw.bin"), good(4096)).unwrap();
        std::fs::write(d.join("other"), elf(&[(FLASH_BASE, FLASH_BASE, &unsealed(4096)[..100], 0)])).unwrap();
        for (input, why) in [("fw.bin", "ELF must be the firmware ELF"), ("other", "ELF must hold its vector table")] {
            let e = run_line(&format!("image {} --bin {} --hex {}", p(input), p("o.bin"), p("o.hex"))).unwrap_err();
            assert!(e.0.starts_with(why), "{}", e.0);
            assert!(!d.join("o.bin").exists() && !d.join("o.hex").exists());
        }
        let e = run_line(&format!("image {} --bin {} --hex {}", p("fw.bin"), p("x"), p("x"))).unwrap_err();
        assert!(e.0.starts_with("ELF must be the firmware ELF"), "{}", e.0);
        // a good ELF, the .hex unwritable: no .bin either
        std::fs::write(d.join("fw"), elf(&[(FLASH_BASE, FLASH_BASE, &unsealed(4096), 0)])).unwrap();
        let e = run_line(&format!("image {} --bin {} --hex /nonexistent-dir/o.hex", p("fw"), p("o.bin"))).unwrap_err();
        assert!(e.0.starts_with("--hex could not write '/nonexistent-dir/o.hex'"), "{}", e.0);
        assert!(!d.join("o.bin").exists());
    }

    #[cfg(unix)]
    #[test]
    fn the_release_files_never_overwrite_the_elf_however_it_is_spelt() {
        let d = dir("self");
        let file = elf(&[(FLASH_BASE, FLASH_BASE, &unsealed(4096), 0)]);
        std::fs::write(d.join("fw"), &file).unwrap();
        std::fs::hard_link(d.join("fw"), d.join("hard")).unwrap();
        let _ = std::os::unix::fs::symlink("fw", d.join("soft"));
        let p = |n: &str| d.join(n).display().to_string();
        for out in [p("fw"), format!("{}/./fw", d.display()), p("hard"), p("soft")] {
            let e = run_line(&format!("image {} --bin {} --hex {}", p("fw"), p("o.hex"), out)).unwrap_err();
            assert!(e.0.starts_with("--hex must not be the ELF it reads (got '"), "{}", e.0);
            let e = run_line(&format!("image {} --bin {out} --hex {}", p("soft"), p("o.hex"))).unwrap_err();
            assert!(e.0.starts_with("--bin must not be the ELF it reads"), "{}", e.0);
        }
        assert_eq!(std::fs::read(d.join("fw")).unwrap(), file);
        assert!(!d.join("o.hex").exists());
    }
}
