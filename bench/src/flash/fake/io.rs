//! The fake ROM's requests (DFU 1.1 §6 state machine, with AN3156's DfuSe
//! meaning of the block number).

use super::{Event, FakeError, FakeRom, Inner, Pending, FLASH_END, TRANSFER};
use dfu_core::functional_descriptor::FunctionalDescriptor;
use dfu_core::memory_layout::MemoryLayout;
use dfu_core::{DfuIo, DfuProtocol, State, Status};
use polyturn_host::flash::FLASH_BASE;

const DNLOAD: u8 = 1;
const UPLOAD: u8 = 2;
const GETSTATUS: u8 = 3;
const CLRSTATUS: u8 = 4;
const GETSTATE: u8 = 5;
const ABORT: u8 = 6;

impl Inner {
    fn get_status(&mut self, buf: &mut [u8]) -> Result<usize, FakeError> {
        match self.state {
            // AN3156 §5.2/§5.3: the command runs at this GETSTATUS
            State::DfuDnloadSync => {
                let pending = std::mem::replace(&mut self.pending, Pending::Nothing);
                self.outcome = self.run(pending);
                self.state = State::DfuDnbusy;
            }
            State::DfuDnbusy if !self.faults.stuck_busy => match self.outcome {
                Ok(()) => self.state = State::DfuDnloadIdle,
                Err(status) => (self.state, self.status) = (State::DfuError, status),
            },
            // AN3156 §5.5: answers dfuMANIFEST, then jumps to the application
            State::DfuManifestSync => {
                self.state = State::DfuManifest;
                self.gone = true;
            }
            _ => {}
        }
        let p = self.faults.poll_ms.to_le_bytes();
        let reply = [self.status.into(), p[0], p[1], p[2], self.state.into(), 0];
        let n = reply.len().min(buf.len());
        buf[..n].copy_from_slice(&reply[..n]);
        Ok(n)
    }

    fn download(&mut self, block: u16, data: &[u8]) -> Result<usize, FakeError> {
        if !matches!(self.state, State::DfuIdle | State::DfuDnloadIdle) || data.len() > usize::from(TRANSFER) {
            return Err(self.stall());
        }
        let word = |d: &[u8]| u32::from_le_bytes([d[1], d[2], d[3], d[4]]);
        self.pending = match (block, data) {
            (_, []) if self.state == State::DfuDnloadIdle => {
                self.state = State::DfuManifestSync;
                self.events.push(Event::Leave);
                return Ok(0);
            }
            (0, [0x21, _, _, _, _]) => Pending::SetAddress(word(data)),
            (0, [0x41, _, _, _, _]) => Pending::Erase(word(data)),
            (0, [0x41]) => Pending::MassErase,
            // AN3156 §5.1: block n at pointer + (n - 2) × wTransferSize
            (2.., [_, ..]) => {
                Pending::Write(self.pointer + (u32::from(block) - 2) * u32::from(TRANSFER), data.to_vec())
            }
            _ => return Err(self.stall()),
        };
        self.state = State::DfuDnloadSync;
        Ok(data.len())
    }

    fn upload(&mut self, block: u16, buf: &mut [u8]) -> Result<usize, FakeError> {
        if !matches!(self.state, State::DfuIdle | State::DfuUploadIdle) {
            return Err(self.stall());
        }
        // AN3156 §4.1: address = (wBlockNum - 2) × wLength + pointer
        let address = u64::from(self.pointer) + u64::from(block.saturating_sub(2)) * buf.len() as u64;
        if block < 2 || address + buf.len() as u64 > u64::from(FLASH_END) {
            (self.state, self.status) = (State::DfuError, Status::ErrTarget);
            return Err(FakeError("stall (errTARGET)".into()));
        }
        let at = (address - u64::from(FLASH_BASE)) as usize;
        buf.copy_from_slice(&self.flash[at..at + buf.len()]);
        self.events.push(Event::Upload { address: address as u32, len: buf.len() });
        self.state = State::DfuUploadIdle;
        Ok(buf.len())
    }
}

impl DfuIo for FakeRom {
    type Read = usize;
    type Write = usize;
    type Reset = ();
    type Error = FakeError;
    type MemoryLayout = MemoryLayout;

    fn read_control(&self, request_type: u8, request: u8, value: u16, buf: &mut [u8]) -> Result<usize, FakeError> {
        let mut s = self.transfer()?;
        match (request_type & 0x7F, request) {
            (0x21, GETSTATUS) => s.get_status(buf),
            (0x21, UPLOAD) => s.upload(value, buf),
            (0x21, GETSTATE) if !buf.is_empty() => {
                buf[0] = s.state.into();
                Ok(1)
            }
            _ => Err(s.stall()),
        }
    }

    fn write_control(&self, request_type: u8, request: u8, value: u16, data: &[u8]) -> Result<usize, FakeError> {
        let mut s = self.transfer()?;
        match (request_type, request) {
            (0x21, DNLOAD) => s.download(value, data),
            (0x21, CLRSTATUS) if s.state == State::DfuError => {
                (s.state, s.status) = (State::DfuIdle, Status::Ok);
                s.events.push(Event::ClearStatus);
                Ok(0)
            }
            (0x21, ABORT) if matches!(s.state, State::DfuIdle | State::DfuDnloadIdle | State::DfuUploadIdle) => {
                s.state = State::DfuIdle;
                s.events.push(Event::Abort);
                Ok(0)
            }
            _ => Err(s.stall()),
        }
    }

    fn usb_reset(self) -> Result<(), FakeError> {
        Err(FakeError("a USB reset: the ROM jumps by itself after leaving (AN3156 §5.5)".into()))
    }

    fn protocol(&self) -> &DfuProtocol<MemoryLayout> {
        &self.protocol
    }

    fn functional_descriptor(&self) -> &FunctionalDescriptor {
        &self.descriptor
    }
}
