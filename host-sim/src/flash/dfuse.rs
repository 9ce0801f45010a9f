//! Flashing through the STM32 ROM bootloader's DfuSe (AN3156): erase and
//! write with dfu-core's DfuSe state machine, read everything back, and
//! only then leave DFU so the board starts the new image.
//!
//! The download is dfu-core's (`download.rs`), the read-back and the
//! leave request are AN3156's own (`readback.rs`).

use super::dfuse_io as req;
pub use super::dfuse_io::Io;
use super::image::Image;
pub use super::plan::Plan;
use std::time::Duration;

mod download;
mod readback;

/// How long the device may take: one step (a sector erase, a block's
/// write) and one poll. A 128 KiB sector erases in at most 4 s at x8
/// parallelism (DS10314 t_ERASE128KB; the ROM's own choice is not
/// documented), so 10 s per step.
#[derive(Clone, Debug)]
pub struct Limits {
    pub step: Duration,
    pub poll_max: Duration,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits { step: Duration::from_secs(10), poll_max: Duration::from_secs(1) }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    Erased { sectors_done: usize, sectors: usize },
    Written { bytes_done: usize, bytes: usize },
    Verified { bytes_done: usize, bytes: usize },
    Leaving,
}

/// How leaving DFU went: the ROM answered dfuMANIFEST, or vanished from
/// the bus before answering (it may jump at once; dfu-util's leave quirk).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Left {
    Manifest,
    Vanished,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Report {
    pub written_bytes: usize,
    pub sectors_erased: usize,
    pub left: Left,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FlashError {
    Usb {
        step: String,
        error: String,
    },
    Device {
        step: String,
        status: String,
    },
    Protocol {
        step: String,
        what: String,
    },
    Timeout {
        step: String,
        waited_ms: u64,
    },
    /// The device is not one this may write (layout, descriptor).
    Refused(String),
    Verify {
        address: u32,
        wrote: u8,
        read: u8,
    },
}

impl std::fmt::Display for FlashError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FlashError::Usb { step, error } => write!(f, "USB transfer failed during {step}: {error}"),
            FlashError::Device { step, status } => write!(f, "the bootloader refused {step}: {status}"),
            FlashError::Protocol { step, what } => write!(f, "{step}: {what}"),
            FlashError::Timeout { step, waited_ms } => {
                write!(f, "{step}: the bootloader was still busy after {waited_ms} ms")
            }
            FlashError::Refused(why) => write!(f, "{why}"),
            FlashError::Verify { address, wrote, read } => {
                write!(f, "verify failed at 0x{address:08x}: wrote 0x{wrote:02x}, read back 0x{read:02x}")
            }
        }
    }
}

/// Erases and writes the image, reads it back, leaves DFU.
pub fn flash<IO: Io>(
    io: &IO,
    image: &Image,
    limits: &Limits,
    progress: &mut dyn FnMut(Progress),
) -> Result<Report, FlashError>
where
    IO::Error: std::fmt::Display,
{
    let plan = plan(io, image)?;
    req::to_idle(io, "the start")?;
    download::download(io, &plan, limits, progress)?;
    readback::verify(io, &plan, limits, progress)?;
    progress(Progress::Leaving);
    let left = readback::leave(io, limits)?;
    Ok(Report { written_bytes: image.bytes.len(), sectors_erased: plan.sectors, left })
}

/// The plan for this device (`plan.rs`), from its descriptor and layout.
fn plan<IO: Io>(io: &IO, image: &Image) -> Result<Plan, FlashError> {
    super::plan::plan(io.functional_descriptor(), io.protocol(), image).map_err(FlashError::Refused)
}
