//! `polyturn flash`: writes a firmware image through the board's ROM
//! bootloader over USB (no probe): checked first, erased and written,
//! read back, then the board restarted into it. Sectors 6-7 (settings,
//! cam tables) are never erased or written.

mod source;

use super::carried;
use super::errors::{escaped, CliError, CliResult};
use super::image::summary;
use super::values::within;
use crate::flash::dfuse::{self, FlashError, Io, Left, Limits, Progress, Report};
use crate::flash::usb;
use crate::flash::Image;
use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

#[derive(clap::Args, Debug)]
pub struct FlashArgs {
    /// The image: .bin, Intel .hex or ELF [default: the image a release polyturn carries, else target/thumbv7em-none-eabihf/fw/polyturn-firmware, as `cargo fw` builds it]
    #[arg(value_name = "FILE")]
    pub file: Option<PathBuf>,
    /// Write an image without the polyturn marker (address, size and vector table checks still apply; an image marked for another chip is still refused)
    #[arg(long)]
    pub any_image: bool,
    /// How long to look for the bootloader on USB, seconds
    // a leading '-' is a value (`-inf`), refused naming --wait, not flags
    #[arg(long, value_name = "S", default_value = "10", allow_hyphen_values = true, value_parser = within(0.0, 600.0, "s"))]
    pub wait: f64,
    /// Check the image and print what would be written; no USB
    #[arg(long)]
    pub dry_run: bool,
}

pub fn run(a: FlashArgs) -> CliResult<String> {
    let source = source::choose(a.file, carried::firmware(), source::built_elf())?;
    let image = source.load(a.any_image)?;
    if a.dry_run {
        return Ok(source.dry_run(&image));
    }
    let io = usb::open(Duration::from_secs_f64(a.wait)).map_err(|e| CliError(format!("flash: {}", escaped(&e))))?;
    write(&io, &image, &Limits::default(), &mut printer())
}

/// Flashes through any DfuSe device (the board's ROM, or the tests' fake).
pub fn write<IO: Io>(io: &IO, image: &Image, limits: &Limits, progress: &mut dyn FnMut(Progress)) -> CliResult<String>
where
    IO::Error: std::fmt::Display,
{
    let report = dfuse::flash(io, image, limits, progress)
        .map_err(|e| CliError(format!("flash: {}; {}", escaped(&e.to_string()), after(&e))))?;
    Ok(done(image, &report))
}

/// What the board is left with after an error.
fn after(e: &FlashError) -> &'static str {
    match e {
        FlashError::Refused(_) => "nothing was written",
        FlashError::Verify { .. } => {
            "the board stays in its bootloader, not started; sectors 6-7 untouched: run polyturn flash again"
        }
        _ => "the board stays in its bootloader; sectors 6-7 untouched: run polyturn flash again",
    }
}

fn done(image: &Image, r: &Report) -> String {
    let restarted = match r.left {
        Left::Manifest => "the board restarted into the new firmware",
        Left::Vanished => "the board left the bootloader without confirming (tap NRST if it does not start)",
    };
    format!(
        "flashed {}\n{} bytes written and verified, {} sectors erased; sectors 6-7 (settings, cam tables) untouched; {restarted}",
        summary(image),
        r.written_bytes,
        r.sectors_erased
    )
}

/// Progress on stderr: each sector erased, the write and read-back by
/// quarters.
fn printer() -> impl FnMut(Progress) {
    let mut quarter = (0, 0);
    move |p| {
        let line = match p {
            Progress::Erased { sectors_done, sectors } => Some(format!("erased sector {} of {sectors}", sectors_done)),
            Progress::Written { bytes_done, bytes } => step("writing", bytes_done, bytes, &mut quarter.0),
            Progress::Verified { bytes_done, bytes } => step("verifying", bytes_done, bytes, &mut quarter.1),
            Progress::Leaving => Some("restarting the board".into()),
        };
        if let Some(line) = line {
            let _ = writeln!(std::io::stderr().lock(), "{line}");
        }
    }
}

fn step(what: &str, done: usize, of: usize, last: &mut usize) -> Option<String> {
    let q = done * 4 / of.max(1);
    (q > *last).then(|| {
        *last = q;
        format!("{what} {}% ({done} of {of} bytes)", q * 25)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flash::image::{from_bytes, Format};
    use polyturn_bench::flash::fake::{FakeRom, Faults};
    use polyturn_bench::flash::testkit::good;

    fn quick() -> Limits {
        Limits { step: Duration::from_millis(300), poll_max: Duration::from_millis(2) }
    }

    #[test]
    fn a_flash_reports_what_was_written_and_that_the_board_restarted() {
        let image = from_bytes(&good(10_000 - 12), Format::Bin, false).unwrap();
        let out = write(&FakeRom::new(Faults::default()), &image, &quick(), &mut |_| {}).unwrap();
        assert!(out.starts_with("flashed polyturn 0.1.0 for the stm32f411ce: 10000 bytes"), "{out}");
        assert!(out.ends_with("10000 bytes written and verified, 1 sectors erased; sectors 6-7 (settings, cam tables) untouched; the board restarted into the new firmware"), "{out}");
    }

    #[test]
    fn a_bad_read_back_is_one_line_naming_the_address() {
        let image = from_bytes(&good(10_000 - 12), Format::Bin, false).unwrap();
        let rom = FakeRom::new(Faults { stuck_low: Some((0x0800_2000, 0xFF)), ..Faults::default() });
        let e = write(&rom, &image, &quick(), &mut |_| {}).unwrap_err();
        assert!(e.0.starts_with("flash: verify failed at 0x08002000: wrote 0x"), "{}", e.0);
        assert!(
            e.0.ends_with("not started; sectors 6-7 untouched: run polyturn flash again") && e.0.lines().count() == 1
        );
    }

    #[test]
    fn progress_is_printed_by_quarters() {
        let mut last = 0;
        let lines: Vec<_> = (1..=8).filter_map(|i| step("writing", i * 1000, 8000, &mut last)).collect();
        assert_eq!(
            lines,
            [
                "writing 25% (2000 of 8000 bytes)",
                "writing 50% (4000 of 8000 bytes)",
                "writing 75% (6000 of 8000 bytes)",
                "writing 100% (8000 of 8000 bytes)"
            ]
        );
    }
}
