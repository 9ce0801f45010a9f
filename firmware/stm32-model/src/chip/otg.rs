//! USB OTG_FS in device mode (RM0383 §22), as embassy-usb-synopsys-otg drives it,
//! with the bus side ([`Otg::setup`], [`Otg::out`], [`Otg::in_token`], SOF, reset)
//! for an emulated host. Sections are RM0383's; RM0090 §34 describes the same core.
//!
//! - §22.16.1: the registers at 0x000-0xE00; the FIFO windows at 0x1000 + n·0x1000
//!   (n < 4): a read of any window pops the shared RX FIFO, a write to window n
//!   pushes into the TX FIFO of IN endpoint n (its DIEPCTL.TXFNUM).
//! - §22.11.1 the RX FIFO holds status words and packet data within GRXFSIZ words;
//!   §22.11.2 one TX FIFO per IN endpoint within DIEPTXF0/DIEPTXFx words; §22.13
//!   320 words in all, checked when a FIFO takes data.
//! - §22.2: 4 IN and 4 OUT endpoints, EP0 the control endpoint.
//! - The AHB master is never busy (GRSTCTL.AHBIDL reads 1) and the soft resets
//!   and FIFO flushes are done by the next read (their bits read 0).
//! - Not modelled (an access panics with "not modelled"): host mode (FHMOD,
//!   HSRST, FCRST), the core soft reset (CSRST), the global NAK commands, byte/halfword writes, direct FIFO
//!   access at 0x20000, reserved offsets. Suspend/resume, data toggles and
//!   isochronous frames are not modelled: the host never idles the bus and
//!   never loses a handshake. GHWCFG4 (0x050, reserved in RM0383) reads 0: the
//!   driver reads it and uses it only for high-speed PHYs.

mod ep;
mod fifo;
mod global;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_wire;
mod wire;

pub use wire::{Handshake, InReply};

use super::RegFile;
use ep::Ep;
use fifo::{RxFifo, TxFifo};

/// Register offsets (§22.16.1 table 124).
pub mod reg {
    pub const GOTGCTL: u32 = 0x000;
    pub const GOTGINT: u32 = 0x004;
    pub const GAHBCFG: u32 = 0x008;
    pub const GUSBCFG: u32 = 0x00C;
    pub const GRSTCTL: u32 = 0x010;
    pub const GINTSTS: u32 = 0x014;
    pub const GINTMSK: u32 = 0x018;
    pub const GRXSTSR: u32 = 0x01C;
    pub const GRXSTSP: u32 = 0x020;
    pub const GRXFSIZ: u32 = 0x024;
    pub const DIEPTXF0: u32 = 0x028;
    pub const GCCFG: u32 = 0x038;
    pub const CID: u32 = 0x03C;
    pub const GHWCFG4: u32 = 0x050;
    pub const HPTXFSIZ: u32 = 0x100;
    /// DIEPTXFx, x = 1..3, at 0x104 + (x-1)·4
    pub const DIEPTXF1: u32 = 0x104;
    pub const DCFG: u32 = 0x800;
    pub const DCTL: u32 = 0x804;
    pub const DSTS: u32 = 0x808;
    pub const DIEPMSK: u32 = 0x810;
    pub const DOEPMSK: u32 = 0x814;
    pub const DAINT: u32 = 0x818;
    pub const DAINTMSK: u32 = 0x81C;
    pub const DVBUSDIS: u32 = 0x828;
    pub const DVBUSPULSE: u32 = 0x82C;
    pub const DIEPEMPMSK: u32 = 0x834;
    /// DIEPCTLn at 0x900 + n·0x20 (DIEPINT +8, DIEPTSIZ +0x10, DTXFSTS +0x18)
    pub const DIEPCTL: u32 = 0x900;
    /// DOEPCTLn at 0xB00 + n·0x20 (DOEPINT +8, DOEPTSIZ +0x10)
    pub const DOEPCTL: u32 = 0xB00;
    pub const PCGCCTL: u32 = 0xE00;
    pub const FIFO: u32 = 0x1000;
}

/// Endpoints per direction, EP0 included (§22.2).
pub const EPS: usize = 4;
/// The FIFO RAM in 32-bit words (§22.2: 1.25 Kbytes).
pub const FIFO_WORDS: u32 = 320;

/// The OTG_FS core: registers, endpoints, FIFOs and the state of the bus.
#[derive(Clone, Debug)]
pub struct Otg {
    regs: RegFile,
    /// GINTSTS's latched (rc_w1) flags
    flags: u32,
    ins: [Ep; EPS],
    outs: [Ep; EPS],
    rx: RxFifo,
    tx: [TxFifo; EPS],
    /// the address the core answers: DCFG.DAD once the control transfer that set
    /// it has ended (see `wire`)
    addr: u8,
    frame: u16,
    enumerated: bool,
    /// a SETUP was taken and its "setup stage done" entry is not yet queued
    setup_stage: bool,
}

impl Default for Otg {
    fn default() -> Otg {
        Otg {
            regs: global::reset_regs(),
            flags: 0,
            ins: [Ep::default(); EPS],
            outs: [Ep::default(); EPS],
            rx: RxFifo::default(),
            tx: Default::default(),
            addr: 0,
            frame: 0,
            enumerated: false,
            setup_stage: false,
        }
    }
}

impl Otg {
    /// A bus read at offset `off` from the base (0x5000_0000).
    pub fn read(&mut self, off: u32) -> u32 {
        match off {
            0x1000..=0x4FFF => self.rx.read_data(),
            0x900..=0xAFF => self.in_read((off - reg::DIEPCTL) / 0x20, off & 0x1F),
            0xB00..=0xCFF => self.out_read((off - reg::DOEPCTL) / 0x20, off & 0x1F),
            _ => self.global_read(off),
        }
    }

    /// A bus write of `value` (lanes `mask`) at `off`.
    pub fn write(&mut self, off: u32, value: u32, mask: u32) {
        if mask != u32::MAX {
            crate::unmodelled(&format!("a byte or halfword write to OTG_FS at offset {off:#x}"));
        }
        match off {
            0x1000..=0x4FFF => self.fifo_write((off - reg::FIFO) / 0x1000, value),
            0x900..=0xAFF => self.in_write((off - reg::DIEPCTL) / 0x20, off & 0x1F, value),
            0xB00..=0xCFF => self.out_write((off - reg::DOEPCTL) / 0x20, off & 0x1F, value),
            _ => self.global_write(off, value),
        }
    }

    /// The OTG_FS interrupt line (§22.15, figure 231): an unmasked GINTSTS flag
    /// (GINTMSK) while GAHBCFG.GINTMSK is set.
    pub fn irq(&self) -> bool {
        self.regs.get(reg::GAHBCFG) & 1 != 0 && self.gintsts() & self.regs.get(reg::GINTMSK) != 0
    }
}
