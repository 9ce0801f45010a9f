//! After the download: the read-back that verifies it, and the request
//! that leaves DFU and starts the application (AN3156 §4.1, §5.5).

use super::super::FLASH_BASE;
use super::io::{self as req, FlashError, Io, Limits, IN, SET_ADDRESS, UPLOAD};
use super::{Left, Plan, Progress};

/// Reads the written range back: the address pointer set, then dfuIDLE
/// (DFU_ABORT, as dfu-util does) and UPLOAD blocks 2, 3, ... (AN3156 §4.1).
pub(super) fn verify<IO: Io>(
    io: &IO,
    plan: &Plan,
    limits: &Limits,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), FlashError>
where
    IO::Error: std::fmt::Display,
{
    req::command(io, SET_ADDRESS, FLASH_BASE, "the read-back address", limits)?;
    req::abort(io, "the read-back")?;
    let mut buf = vec![0u8; plan.transfer];
    for (i, wrote) in plan.bytes.chunks(plan.transfer).enumerate() {
        let address = FLASH_BASE + (i * plan.transfer) as u32;
        let step = format!("the read-back at 0x{address:08x}");
        let n = io.read_control(IN, UPLOAD, (i + 2) as u16, &mut buf).map_err(req::usb(&step))?;
        if n != wrote.len() {
            let _ = req::abort(io, &step);
            return Err(FlashError::Protocol {
                step,
                what: format!("the bootloader sent {n} of {} bytes", wrote.len()),
            });
        }
        if let Some(k) = wrote.iter().zip(&buf).position(|(w, r)| w != r) {
            let _ = req::abort(io, &step);
            return Err(FlashError::Verify { address: address + k as u32, wrote: wrote[k], read: buf[k] });
        }
        progress(Progress::Verified { bytes_done: (i + 1) * plan.transfer, bytes: plan.bytes.len() });
    }
    req::abort(io, "the end of the read-back")
}

/// AN3156 §5.5: the address pointer set to the vector table, a zero-length
/// DNLOAD, then GETSTATUS: the ROM answers dfuMANIFEST and jumps to the
/// application (it is not manifestation tolerant: nothing more is asked).
pub(super) fn leave<IO: Io>(io: &IO, limits: &Limits) -> Result<Left, FlashError>
where
    IO::Error: std::fmt::Display,
{
    req::command(io, SET_ADDRESS, FLASH_BASE, "the start address", limits)?;
    // wValue 2, as dfu-util's dfuse_do_leave sends it
    io.write_control(req::OUT, req::DNLOAD, 2, &[]).map_err(req::usb("the leave request"))?;
    match req::status(io, "the leave request") {
        Ok((_, _, dfu_core::State::DfuManifest)) => Ok(Left::Manifest),
        Ok((status, _, state)) => Err(FlashError::Protocol {
            step: "the leave request".into(),
            what: format!("the bootloader stayed in {state:?} ({status:?})"),
        }),
        Err(FlashError::Usb { .. }) => Ok(Left::Vanished),
        Err(e) => Err(e),
    }
}
