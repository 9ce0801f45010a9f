//! The download: dfu-core's DfuSe state machine, driven as its DfuSync
//! drives it, with two differences. DfuSync ends with the zero-length
//! DNLOAD that makes the ROM leave DFU (AN3156 §5.5) before any read-back;
//! and it polls as long as the device says busy, sleeping whatever
//! bwPollTimeout the device asks. Here the last block is not sent, and
//! every wait is bounded (`io::wait`).

use super::super::FLASH_BASE;
use super::io::{self as req, FlashError, Io, Limits};
use super::{Plan, Progress};
use dfu_core::download::Step;
use dfu_core::DfuSansIo;

/// dfu-core's DfuSe download: erase each page, set the address, then
/// blocks 2, 3, ... (AN3156 §5.1-§5.3); stopped before the zero-length
/// block, which would leave DFU.
pub(super) fn download<IO: Io>(
    io: &IO,
    plan: &Plan,
    limits: &Limits,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), FlashError>
where
    IO::Error: std::fmt::Display,
{
    let dfu = DfuSansIo::new(*io.functional_descriptor());
    let protocol_error =
        |step: &str, e: dfu_core::Error| FlashError::Protocol { step: step.into(), what: e.to_string() };
    let mut buf = [0u8; 6];
    let start = dfu.download(io.protocol(), plan.bytes.len() as u32).map_err(|e| protocol_error("the start", e))?;
    let (cmd, mut control) = start.get_status(&mut buf);
    let n = control.execute(io).map_err(req::usb("the start"))?;
    let (cmd, clear) = cmd.chain(&buf[..n]).map_err(|e| protocol_error("the start", e))?;
    if let Some(clear) = clear {
        clear.execute(io).map_err(req::usb("the start"))?;
    }
    let (cmd, mut control) = cmd.get_status(&mut buf);
    let n = control.execute(io).map_err(req::usb("the start"))?;
    let mut next = cmd.chain(&buf[..n]).and_then(|r| r).map_err(|e| protocol_error("the start", e))?;
    let (mut erased, mut written) = (0, 0);
    loop {
        next = match next.next() {
            Step::Erase(cmd) => {
                let step = format!("the erase of sector {erased}");
                let (wait, control) = cmd.erase().map_err(|e| protocol_error(&step, e))?;
                control.execute(io).map_err(req::usb(&step))?;
                let next = req::wait(io, wait, &step, limits)?;
                erased += 1;
                progress(Progress::Erased { sectors_done: erased, sectors: plan.sectors });
                next
            }
            Step::SetAddress(cmd) => {
                let (wait, control) = cmd.set_address();
                control.execute(io).map_err(req::usb("the write address"))?;
                req::wait(io, wait, "the write address", limits)?
            }
            Step::DownloadChunk(_) if written == plan.bytes.len() => return Ok(()),
            Step::DownloadChunk(cmd) => {
                let step = format!("the write at 0x{:08x}", FLASH_BASE as usize + written);
                let chunk = &plan.bytes[written..written + plan.transfer];
                let (wait, control) = cmd.download(chunk).map_err(|e| protocol_error(&step, e))?;
                let sent = control.execute(io).map_err(req::usb(&step))?;
                if sent != chunk.len() {
                    let what = format!("the bootloader took {sent} of {} bytes", chunk.len());
                    return Err(FlashError::Protocol { step, what });
                }
                let next = req::wait(io, wait, &step, limits)?;
                written += sent;
                progress(Progress::Written { bytes_done: written, bytes: plan.bytes.len() });
                next
            }
            Step::Break | Step::UsbReset => {
                let what = "dfu-core ended the download early".to_string();
                return Err(FlashError::Protocol { step: "the download".into(), what });
            }
        };
    }
}
