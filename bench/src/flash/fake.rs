//! A fake STM32F411 ROM bootloader behind dfu-core's DfuIo, for tests: the
//! DfuSe requests as AN3156 describes them (commands run at the first
//! GETSTATUS, which answers dfuDNBUSY; the second gives dfuDNLOAD-IDLE or
//! dfuERROR with errTARGET; leave at a zero-length DNLOAD), over 512 KiB
//! of flash with the F411's sectors. Erase sets a whole sector to 0xFF;
//! programming only clears bits (NOR flash), so a write over unerased
//! bytes ANDs into them as on the chip. Faults can be injected.

use dfu_core::functional_descriptor::FunctionalDescriptor;
use dfu_core::memory_layout::MemoryLayout;
use dfu_core::{DfuProtocol, State, Status};
use polyturn_host::flash::{sector_start, FLASH_BASE, SECTOR_KIB};
use std::cell::RefCell;

pub const INTERFACE: &str = "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg";
pub const TRANSFER: u16 = 2048;
pub const FLASH_END: u32 = FLASH_BASE + 512 * 1024;

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    Erase(u32),
    MassErase,
    SetAddress(u32),
    Write { address: u32, len: usize },
    Upload { address: u32, len: usize },
    Abort,
    ClearStatus,
    Leave,
}

#[derive(Debug, Clone, Default)]
pub struct Faults {
    /// This control transfer (counting from 0) fails as a USB error.
    pub usb_error_at: Option<usize>,
    /// A weak cell: these bits of this byte stay 0 when it is programmed.
    pub stuck_low: Option<(u32, u8)>,
    /// GETSTATUS answers dfuDNBUSY for ever.
    pub stuck_busy: bool,
    /// bwPollTimeout the fake asks for, ms.
    pub poll_ms: u32,
}

#[derive(Debug)]
pub struct FakeError(pub String);

impl From<dfu_core::Error> for FakeError {
    fn from(e: dfu_core::Error) -> FakeError {
        FakeError(e.to_string())
    }
}

impl std::fmt::Display for FakeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

enum Pending {
    Nothing,
    SetAddress(u32),
    Erase(u32),
    MassErase,
    Write(u32, Vec<u8>),
}

struct Inner {
    flash: Vec<u8>,
    state: State,
    status: Status,
    pointer: u32,
    pending: Pending,
    outcome: Result<(), Status>,
    transfers: usize,
    events: Vec<Event>,
    faults: Faults,
    gone: bool,
}

pub struct FakeRom {
    inner: RefCell<Inner>,
    descriptor: FunctionalDescriptor,
    protocol: DfuProtocol<MemoryLayout>,
}

impl FakeRom {
    /// A fake with this interface string; flash erased.
    pub fn with_interface(interface: &str, faults: Faults) -> FakeRom {
        let descriptor = FunctionalDescriptor {
            can_download: true,
            can_upload: true,
            manifestation_tolerant: false,
            will_detach: true,
            detach_timeout: 255,
            transfer_size: TRANSFER,
            dfu_version: (0x01, 0x1A),
        };
        let protocol = DfuProtocol::new(interface, descriptor.dfu_version).expect("a DfuSe string");
        let inner = Inner {
            flash: vec![0xFF; (FLASH_END - FLASH_BASE) as usize],
            state: State::DfuIdle,
            status: Status::Ok,
            pointer: FLASH_BASE,
            pending: Pending::Nothing,
            outcome: Ok(()),
            transfers: 0,
            events: Vec::new(),
            faults,
            gone: false,
        };
        FakeRom { inner: RefCell::new(inner), descriptor, protocol }
    }

    pub fn new(faults: Faults) -> FakeRom {
        FakeRom::with_interface(INTERFACE, faults)
    }

    /// Puts bytes straight into flash (what was there before the test).
    pub fn preload(&self, address: u32, bytes: &[u8]) {
        let at = (address - FLASH_BASE) as usize;
        self.inner.borrow_mut().flash[at..at + bytes.len()].copy_from_slice(bytes);
    }

    pub fn read(&self, address: u32, len: usize) -> Vec<u8> {
        let at = (address - FLASH_BASE) as usize;
        self.inner.borrow().flash[at..at + len].to_vec()
    }

    pub fn events(&self) -> Vec<Event> {
        self.inner.borrow().events.clone()
    }

    pub fn transfers(&self) -> usize {
        self.inner.borrow().transfers
    }

    pub fn state(&self) -> State {
        self.inner.borrow().state
    }

    /// Every transfer: gone after leaving, or a fault injected.
    fn transfer(&self) -> Result<std::cell::RefMut<'_, Inner>, FakeError> {
        let mut s = self.inner.borrow_mut();
        let n = s.transfers;
        s.transfers += 1;
        if s.gone {
            return Err(FakeError("no such device (it left DFU)".into()));
        }
        if s.faults.usb_error_at == Some(n) {
            return Err(FakeError("pipe error (injected)".into()));
        }
        Ok(s)
    }
}

impl Inner {
    /// A request the state does not allow: the ROM stalls it (AN3156 Figure
    /// "Download request: device side": dfuERROR, errSTALLEDPKT).
    fn stall(&mut self) -> FakeError {
        self.state = State::DfuError;
        self.status = Status::ErrStalledpkt;
        FakeError("stall".into())
    }

    fn sector_of(address: u32) -> Option<u32> {
        (0..SECTOR_KIB.len()).map(sector_start).take_while(|&s| s <= address).last().filter(|_| address < FLASH_END)
    }

    fn run(&mut self, pending: Pending) -> Result<(), Status> {
        let in_flash = |a: u32, len: usize| a >= FLASH_BASE && u64::from(a) + len as u64 <= u64::from(FLASH_END);
        match pending {
            Pending::Nothing => Ok(()),
            Pending::SetAddress(a) if in_flash(a, 0) => {
                self.pointer = a;
                self.events.push(Event::SetAddress(a));
                Ok(())
            }
            Pending::Erase(a) => {
                let start = Inner::sector_of(a).ok_or(Status::ErrTarget)?;
                let n = SECTOR_KIB[(0..8).position(|i| sector_start(i) == start).unwrap_or(0)] as usize * 1024;
                let at = (start - FLASH_BASE) as usize;
                self.flash[at..at + n].fill(0xFF);
                self.events.push(Event::Erase(start));
                Ok(())
            }
            Pending::MassErase => {
                self.flash.fill(0xFF);
                self.events.push(Event::MassErase);
                Ok(())
            }
            Pending::Write(a, data) if in_flash(a, data.len()) => {
                let at = (a - FLASH_BASE) as usize;
                for (i, b) in data.iter().enumerate() {
                    let weak = match self.faults.stuck_low {
                        Some((addr, bits)) if addr == a + i as u32 => bits,
                        _ => 0,
                    };
                    self.flash[at + i] &= b & !weak;
                }
                self.events.push(Event::Write { address: a, len: data.len() });
                Ok(())
            }
            Pending::SetAddress(_) | Pending::Write(..) => Err(Status::ErrTarget),
        }
    }
}

/// The DfuIo side: the requests, one transfer each.
mod descriptors;
mod io;
