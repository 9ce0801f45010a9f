//! Which image `polyturn flash` writes: FILE if given, else the image a
//! release `polyturn` carries (made with it, so always its version), else
//! the ELF `cargo fw` built in this checkout.

use super::super::carried::Firmware;
use super::super::errors::{escaped, CliError, CliResult};
use super::super::image::{load, summary};
use crate::flash::image::{from_bytes, Format};
use crate::flash::{Image, BUILT_ELF};
use std::path::PathBuf;

#[derive(Debug, PartialEq)]
pub enum Source {
    File(PathBuf),
    Carried(Firmware),
}

/// FILE, else `carried`, else `built` if it exists; Err names FILE and
/// both ways to get an image.
pub fn choose(given: Option<PathBuf>, carried: Option<Firmware>, built: PathBuf) -> CliResult<Source> {
    if let Some(f) = given {
        return Ok(Source::File(f));
    }
    if let Some(fw) = carried {
        return Ok(Source::Carried(fw));
    }
    if built.is_file() {
        return Ok(Source::File(built));
    }
    Err(CliError(format!(
        "FILE is required: no firmware built here ('{}' is missing): run `cargo fw` in the polyturn checkout, give a release image (.hex or .bin, as `polyturn image` makes them), or use a release polyturn, which carries its image",
        escaped(&built.display().to_string())
    )))
}

/// Where `cargo fw` leaves the ELF, under CARGO_TARGET_DIR if set.
pub fn built_elf() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) => PathBuf::from(dir).join(BUILT_ELF.trim_start_matches("target/")),
        None => PathBuf::from(BUILT_ELF),
    }
}

impl Source {
    /// The image, checked as any image `polyturn flash` writes.
    pub fn load(&self, any_image: bool) -> CliResult<Image> {
        match self {
            Source::File(path) => load("FILE", path, any_image, None),
            Source::Carried(fw) => from_bytes(fw.bytes, Format::Bin, any_image).map_err(|r| {
                CliError(format!(
                    "the image this polyturn carries ('{}') {} ({})",
                    fw.name,
                    escaped(&r.rule),
                    escaped(&r.found)
                ))
            }),
        }
    }

    /// The dry run's line; a carried image is named, as no file was.
    pub fn dry_run(&self, image: &Image) -> String {
        let what = format!("would write {}; sectors 6-7 (settings, cam tables) stay as they are", summary(image));
        match self {
            Source::File(_) => what,
            Source::Carried(fw) => format!("the image this polyturn carries, {}: {what}", fw.name),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use polyturn_bench::flash::testkit::good;
    use std::sync::LazyLock;

    static BYTES: LazyLock<Vec<u8>> = LazyLock::new(|| good(10_000 - 12));

    fn carried() -> Firmware {
        Firmware { name: "polyturn-0.1.0-stm32f411ce.bin", bytes: &BYTES }
    }

    #[test]
    fn no_file_means_the_carried_image_before_a_built_elf() {
        let elf = std::env::current_exe().unwrap(); // a file that exists
        let given = Some(PathBuf::from("x.bin"));
        assert_eq!(choose(given.clone(), Some(carried()), elf.clone()).unwrap(), Source::File("x.bin".into()));
        assert_eq!(choose(None, Some(carried()), elf.clone()).unwrap(), Source::Carried(carried()));
        assert_eq!(choose(None, None, elf.clone()).unwrap(), Source::File(elf));
        let e = choose(None, None, PathBuf::from("/nonexistent/fw")).unwrap_err().0;
        assert!(e.starts_with("FILE is required: no firmware built here ('/nonexistent/fw' is missing)"), "{e}");
    }

    #[test]
    fn the_carried_image_is_checked_and_named_in_the_dry_run() {
        let source = Source::Carried(carried());
        let line = source.dry_run(&source.load(false).unwrap());
        assert!(
            line.starts_with("the image this polyturn carries, polyturn-0.1.0-stm32f411ce.bin: would write polyturn 0.1.0 for the stm32f411ce: 10000 bytes"),
            "{line}"
        );
        // an unmarked image is refused unless --any-image, as a file is
        let unmarked = Firmware { name: "x.bin", bytes: &[0u8; 64] };
        let e = Source::Carried(unmarked).load(false).unwrap_err().0;
        assert!(e.starts_with("the image this polyturn carries ('x.bin') "), "{e}");
    }
}
