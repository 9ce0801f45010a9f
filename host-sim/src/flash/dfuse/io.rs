//! The bootloader's requests (DFU 1.1 §3 Table 3.2; AN3156 for what the
//! STM32 ROM does with them), each one control transfer, every wait for
//! the device bounded by `Limits::step`.

use dfu_core::get_status::{Step, WaitState};
use dfu_core::{DfuIo, State, Status};
use std::time::{Duration, Instant};

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

/// Class request to the interface; bit 7 set for device-to-host.
pub const OUT: u8 = 0x21;
pub const IN: u8 = 0xA1;
pub const DNLOAD: u8 = 1;
pub const UPLOAD: u8 = 2;
pub const GETSTATUS: u8 = 3;
pub const CLRSTATUS: u8 = 4;
pub const ABORT: u8 = 6;
/// DfuSe's Set Address Pointer, DNLOAD block 0 (AN3156 §5.2); dfu-core
/// sends the erases (0x41, §5.3).
pub const SET_ADDRESS: u8 = 0x21;

/// What DfuIo needs here: transfers that give byte counts.
pub trait Io: DfuIo<Read = usize, Write = usize> {}
impl<T: DfuIo<Read = usize, Write = usize>> Io for T {}

pub fn usb<E: std::fmt::Display>(step: &str) -> impl FnOnce(E) -> FlashError + '_ {
    move |e| FlashError::Usb { step: step.to_string(), error: e.to_string() }
}

/// DFU_GETSTATUS: (bStatus, bwPollTimeout ms, bState).
pub fn status<IO: Io>(io: &IO, step: &str) -> Result<(Status, u64, State), FlashError>
where
    IO::Error: std::fmt::Display,
{
    let mut buf = [0u8; 6];
    let n = io.read_control(IN, GETSTATUS, 0, &mut buf).map_err(usb(step))?;
    if n < 6 {
        return Err(FlashError::Protocol { step: step.into(), what: format!("a status of {n} bytes, not 6") });
    }
    let poll_ms = u64::from(u32::from_le_bytes([buf[1], buf[2], buf[3], 0]));
    Ok((Status::from(buf[0]), poll_ms, State::from(buf[4])))
}

/// Back to dfuIDLE from wherever an earlier session left the device: an
/// error cleared (DFU_CLRSTATUS), a transfer aborted (DFU_ABORT), as AN3156
/// §4 asks before an upload and DfuSync's download expects.
pub fn to_idle<IO: Io>(io: &IO, step: &str) -> Result<(), FlashError>
where
    IO::Error: std::fmt::Display,
{
    for _ in 0..3 {
        match status(io, step)?.2 {
            State::DfuIdle => return Ok(()),
            State::DfuError => io.write_control(OUT, CLRSTATUS, 0, &[]).map(drop).map_err(usb(step))?,
            State::DfuDnloadIdle | State::DfuUploadIdle => {
                io.write_control(OUT, ABORT, 0, &[]).map(drop).map_err(usb(step))?
            }
            other => {
                return Err(FlashError::Protocol {
                    step: step.into(),
                    what: format!("the bootloader is in state {other:?}"),
                })
            }
        }
    }
    Err(FlashError::Protocol { step: step.into(), what: "the bootloader does not return to dfuIDLE".into() })
}

/// Polls DFU_GETSTATUS until `wait` is satisfied, sleeping as the device
/// asks (at most Limits::poll_max a time) and no longer than Limits::step
/// in all. A device that reports dfuERROR is read and cleared, and its
/// status named.
pub fn wait<IO: Io, T>(io: &IO, mut wait: WaitState<T>, step: &str, limits: &Limits) -> Result<T, FlashError>
where
    IO::Error: std::fmt::Display,
{
    let start = Instant::now();
    let mut buf = [0u8; 6];
    loop {
        let (cmd, poll_ms) = match wait.next() {
            Step::Break(done) => return Ok(done),
            Step::Wait(cmd, poll_ms) => (cmd, poll_ms),
        };
        let waited = start.elapsed();
        if waited >= limits.step {
            return Err(FlashError::Timeout { step: step.into(), waited_ms: waited.as_millis() as u64 });
        }
        std::thread::sleep(limits.poll_max.min(std::time::Duration::from_millis(poll_ms)).min(limits.step - waited));
        let (cmd, mut control) = cmd.get_status(&mut buf);
        let n = control.execute(io).map_err(usb(step))?;
        wait = match cmd.chain(&buf[..n]) {
            Ok(Ok(next)) => next,
            Ok(Err(dfu_core::Error::InvalidState { got: State::DfuError, .. })) => return Err(device_error(io, step)),
            Ok(Err(e)) | Err(e) => return Err(FlashError::Protocol { step: step.into(), what: e.to_string() }),
        };
    }
}

/// The error a device in dfuERROR reports; cleared so the next session
/// finds it idle (AN3156 §4: the host clears any error).
pub fn device_error<IO: Io>(io: &IO, step: &str) -> FlashError
where
    IO::Error: std::fmt::Display,
{
    let status = match status(io, step) {
        Ok((s, _, _)) => s,
        Err(e) => return e,
    };
    let _ = io.write_control(OUT, CLRSTATUS, 0, &[]);
    FlashError::Device { step: step.into(), status: status_name(status) }
}

/// A DfuSe command (DNLOAD block 0) and its two GETSTATUS: dfuDNBUSY while
/// it runs, then dfuDNLOAD-IDLE (AN3156 §5.2, §5.3).
pub fn command<IO: Io>(io: &IO, code: u8, address: u32, step: &str, limits: &Limits) -> Result<(), FlashError>
where
    IO::Error: std::fmt::Display,
{
    let a = address.to_le_bytes();
    io.write_control(OUT, DNLOAD, 0, &[code, a[0], a[1], a[2], a[3]]).map_err(usb(step))?;
    wait(io, WaitState::new(State::DfuDnbusy, State::DfuDnloadIdle, ()), step, limits)
}

pub fn abort<IO: Io>(io: &IO, step: &str) -> Result<(), FlashError>
where
    IO::Error: std::fmt::Display,
{
    io.write_control(OUT, ABORT, 0, &[]).map(drop).map_err(usb(step))
}

/// The DFU 1.1 status names, with what the STM32 ROM means by the two it
/// uses for refusals (AN3156 §5.2, §5.3).
fn status_name(s: Status) -> String {
    match s {
        Status::ErrTarget => "errTARGET (an address the bootloader does not allow)".into(),
        Status::ErrVendor => "errVENDOR (flash read protection is on)".into(),
        Status::ErrStalledpkt => "errSTALLEDPKT (a request it does not support)".into(),
        other => format!("{other:?} ({other})"),
    }
}
