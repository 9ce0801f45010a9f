//! Flashing through the STM32 ROM bootloader's DfuSe (AN3156): erase and
//! write with dfu-core's DfuSe state machine, read everything back, and
//! only then leave DFU so the board starts the new image.
//!
//! The download is dfu-core's (`download.rs`), the read-back and the
//! leave request are AN3156's own (`readback.rs`), each request one control
//! transfer (`io.rs`, with the errors and the time limits).

pub use super::plan::Plan;
use super::Image;
use io as req;
pub use io::{FlashError, Io, Limits};

mod download;
pub(super) mod io;
mod readback;

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
