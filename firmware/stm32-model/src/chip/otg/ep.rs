//! The endpoint registers (§22.16.4): DIEPCTLx/DOEPCTLx, DIEPINTx/DOEPINTx,
//! DIEPTSIZx/DOEPTSIZx, DTXFSTSx, and the FIFO windows' writes.

use super::{global::ENUMDNE, reg::*, Otg, EPS};
use crate::unmodelled;

pub const EPENA: u32 = 1 << 31;
pub const EPDIS: u32 = 1 << 30;
pub const SNAK: u32 = 1 << 27;
pub const CNAK: u32 = 1 << 26;
pub const STALL: u32 = 1 << 21;
pub const NAKSTS: u32 = 1 << 17;
pub const USBAEP: u32 = 1 << 15;
/// DIEPINT/DOEPINT XFRC, EPDISD, DOEPINT.STUP, DIEPINT.INEPNE and TXFE
pub const XFRC: u32 = 1 << 0;
pub const EPDISD: u32 = 1 << 1;
pub const STUP: u32 = 1 << 3;
const INEPNE: u32 = 1 << 6;
pub const TXFE: u32 = 1 << 7;
/// DxEPCTLn's read/write fields: MPSIZ, USBAEP, EPTYP, SNPM (OUT), TXFNUM (IN);
/// on EP0, MPSIZ is 2 bits and EPTYP reads 00 (control).
const RW_N: u32 = 0x7FF | USBAEP | 0b11 << 18 | 1 << 20 | 0xF << 22;
const RW_0: u32 = 0b11;

/// One endpoint's control, interrupt and transfer size registers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ep {
    pub ctl: u32,
    pub int: u32,
    pub siz: u32,
}

impl Ep {
    pub fn has(&self, bit: u32) -> bool {
        self.ctl & bit != 0
    }

    /// The maximum packet size: MPSIZ, coded on EP0 (00: 64, 01: 32, 10: 16, 11: 8).
    pub fn mps(&self, n: usize) -> usize {
        if n == 0 {
            64 >> (self.ctl & 3)
        } else {
            (self.ctl & 0x7FF) as usize
        }
    }

    /// DxEPTSIZn's PKTCNT and XFRSIZ.
    pub fn pktcnt(&self) -> u32 {
        self.siz >> 19 & 0x3FF
    }

    pub fn xfrsiz(&self) -> u32 {
        self.siz & 0x7_FFFF
    }

    /// One packet of `len` bytes done: XFRSIZ and PKTCNT decremented; true
    /// when that ends the transfer (PKTCNT 0, or a short packet).
    pub fn count(&mut self, len: usize, mps: usize) -> bool {
        let x = self.xfrsiz().saturating_sub(len as u32);
        let p = self.pktcnt().saturating_sub(1);
        self.siz = self.siz & !(0x3FF << 19 | 0x7_FFFF) | p << 19 | x;
        p == 0 || len < mps
    }

    /// A DxEPCTLn write (§22.16.4): the rw fields; EPENA and (on EP0) STALL set
    /// only by software; EPDIS on an enabled endpoint disables it (EPENA cleared,
    /// EPDISD raised); SNAK/CNAK set/clear NAKSTS (both at once: undefined).
    fn write_ctl(&mut self, n: usize, is_in: bool, v: u32) {
        let rw = if n == 0 { RW_0 } else { RW_N | STALL };
        let mut c = self.ctl & !rw | v & rw;
        if n == 0 {
            c |= v & STALL;
        }
        c |= v & EPENA;
        match (v & SNAK != 0, v & CNAK != 0) {
            (true, true) => unmodelled(&format!("SNAK and CNAK together on endpoint {n} (undefined, §22.16.4)")),
            (true, false) => {
                c |= NAKSTS;
                if is_in {
                    self.int |= INEPNE;
                }
            }
            (false, true) => c &= !NAKSTS,
            _ => {}
        }
        if v & EPDIS != 0 && c & EPENA != 0 {
            c &= !EPENA;
            self.int |= EPDISD;
        }
        self.ctl = c;
    }

    /// DxEPCTLn as read: the write-only commands (SNAK, CNAK, SD0PID, SODDFRM:
    /// data toggles are not modelled) read 0; EP0 is always active (USBAEP, its
    /// DOEPCTL0 reset value 0x0000_8000).
    fn read_ctl(&self, n: usize) -> u32 {
        self.ctl | if n == 0 { USBAEP } else { 0 }
    }
}

impl Otg {
    fn ep_index(n: u32) -> usize {
        if n as usize >= EPS {
            unmodelled(&format!("OTG_FS endpoint {n} (the core has {EPS})"));
        }
        n as usize
    }

    /// The TX FIFO of IN endpoint `n`: its DIEPCTL.TXFNUM, EP0's FIFO 0 (§22.16.4).
    pub(super) fn fifo_of(&self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            Self::ep_index(self.ins[n].ctl >> 22 & 0xF)
        }
    }

    /// DIEPINTn with TXFE: the TX FIFO half empty (GAHBCFG.TXFELVL = 0) or
    /// empty (= 1) (§22.16.4 DIEPINT, §22.16.2 GAHBCFG).
    pub(super) fn diepint(&self, n: usize) -> u32 {
        let f = self.fifo_of(n);
        let (used, size) = (self.tx[f].words() as u32, self.tx_fifo(f).1);
        let empty = if self.regs.get(GAHBCFG) >> 7 & 1 == 1 { used == 0 } else { 2 * used <= size };
        self.ins[n].int | if empty { TXFE } else { 0 }
    }

    pub(super) fn in_read(&mut self, n: u32, r: u32) -> u32 {
        let n = Self::ep_index(n);
        match r {
            0x00 => self.ins[n].read_ctl(n),
            0x08 => self.diepint(n),
            0x10 => self.ins[n].siz,
            // DTXFSTS: the words free in the endpoint's TX FIFO
            0x18 => {
                let f = self.fifo_of(n);
                self.tx_fifo(f).1.saturating_sub(self.tx[f].words() as u32)
            }
            _ => unmodelled(&format!("read of OTG_FS IN endpoint {n} register +{r:#x}")),
        }
    }

    pub(super) fn out_read(&mut self, n: u32, r: u32) -> u32 {
        let n = Self::ep_index(n);
        match r {
            0x00 => self.outs[n].read_ctl(n),
            0x08 => self.outs[n].int,
            0x10 => self.outs[n].siz,
            _ => unmodelled(&format!("read of OTG_FS OUT endpoint {n} register +{r:#x}")),
        }
    }

    pub(super) fn in_write(&mut self, n: u32, r: u32, v: u32) {
        let n = Self::ep_index(n);
        let e = &mut self.ins[n];
        match r {
            0x00 => e.write_ctl(n, true, v),
            0x08 => e.int &= !(v & !TXFE),
            // MCNT, PKTCNT, XFRSIZ (EP0: PKTCNT 2 bits, XFRSIZ 7)
            0x10 => e.siz = v & if n == 0 { 0x3 << 19 | 0x7F } else { 0x7FFF_FFFF },
            0x18 => {}
            _ => unmodelled(&format!("write {v:#x} to OTG_FS IN endpoint {n} register +{r:#x}")),
        }
    }

    pub(super) fn out_write(&mut self, n: u32, r: u32, v: u32) {
        let n = Self::ep_index(n);
        let e = &mut self.outs[n];
        match r {
            0x00 => e.write_ctl(n, false, v),
            0x08 => e.int &= !v,
            // STUPCNT, PKTCNT, XFRSIZ (EP0: PKTCNT 1 bit, XFRSIZ 7); RXDPID read-only
            0x10 => e.siz = v & if n == 0 { 0x3 << 29 | 1 << 19 | 0x7F } else { 0x1FFF_FFFF },
            _ => unmodelled(&format!("write {v:#x} to OTG_FS OUT endpoint {n} register +{r:#x}")),
        }
    }

    /// A word written at FIFO window `n` goes to the TX FIFO of IN endpoint n,
    /// its DIEPCTL.TXFNUM (EP0: FIFO 0) (§22.11.2, §22.16.1). Past the FIFO's
    /// size (DIEPTXFx.INEPTXFD) is an overrun the model does not take.
    pub(super) fn fifo_write(&mut self, n: u32, v: u32) {
        let f = self.fifo_of(Self::ep_index(n));
        self.check_layout(Some(f));
        if self.tx[f].words() as u32 >= self.tx_fifo(f).1 {
            unmodelled(&format!("a write past the end of TX FIFO {f} (overrun)"));
        }
        self.tx[f].push(v);
    }

    /// A USB reset (§22.17.5 "Endpoint initialization on USB reset"): the core
    /// deactivates endpoints 1-3 (USBAEP, EPENA cleared), answers address 0, and
    /// raises USBRST; ENUMDNE comes when the reset ends.
    pub(super) fn reset_endpoints(&mut self) {
        for e in self.ins.iter_mut().chain(self.outs.iter_mut()) {
            e.ctl &= !EPENA;
        }
        for n in 1..EPS {
            self.ins[n].ctl &= !USBAEP;
            self.outs[n].ctl &= !USBAEP;
        }
        self.flags &= !ENUMDNE;
    }
}
