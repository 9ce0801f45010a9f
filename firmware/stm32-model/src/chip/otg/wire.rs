//! The USB side: what a host on the cable does to the core, one transaction at a
//! time (§22.17.5 device programming model, §22.17.6 operational model). The core
//! answers only while pulled up and only at its address (`Otg::addr`).
//!
//! - A SETUP on EP0 is always taken (DOEPCTL.NAKSTS: "irrespective of this bit,
//!   the core always responds to SETUP data packets with an ACK"): SETUP data into
//!   the RX FIFO, STUPCNT decremented, STALL cleared and NAK set on both EP0
//!   directions; the next IN or OUT token on EP0 queues "setup stage done", whose
//!   pop raises DOEPINT.STUP.
//! - An OUT data packet is taken while the endpoint is active, not stalled, its
//!   NAK clear and the RX FIFO has room; PKTCNT/XFRSIZ count it, and at the end
//!   of the transfer the core sets NAK and queues "OUT transfer completed", whose
//!   pop raises DOEPINT.XFRC and clears EPENA. (EPENA is not required to take a
//!   packet: embassy-usb-synopsys-otg re-arms OUT endpoints with CNAK alone and
//!   works on silicon.)
//! - An IN token gets a packet once the endpoint is enabled, NAK clear and a
//!   whole packet (MPSIZ or the rest of XFRSIZ) is in its TX FIFO; at PKTCNT 0,
//!   DIEPINT.XFRC and EPENA cleared. A new DCFG.DAD is answered from the end of
//!   the control transfer that set it (its IN status stage, USB 2.0 §9.4.6).

use super::ep::{EPENA, NAKSTS, STALL, STUP, USBAEP, XFRC};
use super::fifo::{status, OUT_DATA, OUT_DONE, SETUP_DATA, SETUP_DONE};
use super::global::{ENUMDNE, EOPF, SOF, USBRST};
use super::{reg::DCFG, Otg, EPS};

/// The RX FIFO words kept for SETUP packets on the control endpoint: "10
/// locations must be reserved in the receive FIFO to receive SETUP packets
/// ... The core does not use these locations ... to write any other data"
/// (§22.11.1, device-mode FIFO RAM allocation).
pub const SETUP_RESERVE: usize = 10;

/// The device's answer to a SETUP or OUT packet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handshake {
    Ack,
    Nak,
    Stall,
    /// no answer: not connected, another address, or an inactive endpoint
    Timeout,
}

/// The device's answer to an IN token.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum InReply {
    Data(Vec<u8>),
    Nak,
    Stall,
    Timeout,
}

impl Otg {
    /// USB reset signalling begins (§22.15 USBRST).
    pub fn bus_reset(&mut self) {
        self.reset_endpoints();
        self.addr = 0;
        self.enumerated = false;
        self.setup_stage = false;
        self.flags |= USBRST;
    }

    /// The reset ends and the speed is enumerated: full speed (§22.16.4 DSTS,
    /// §22.15 ENUMDNE).
    pub fn reset_done(&mut self) {
        self.enumerated = true;
        self.flags |= ENUMDNE;
    }

    /// A start of frame (§22.15 SOF): DSTS.FNSOF = `frame`.
    pub fn sof(&mut self, frame: u16) {
        self.frame = frame & 0x7FF;
        self.flags |= SOF;
    }

    /// The end of the periodic frame (DCFG.PFIVL of the frame, §22.15 EOPF).
    pub fn end_of_periodic_frame(&mut self) {
        self.flags |= EOPF;
    }

    /// DCFG.PFIVL as a percentage of the frame: 80, 85, 90 or 95.
    pub fn periodic_frame_percent(&self) -> u32 {
        80 + 5 * (self.regs.get(DCFG) >> 11 & 3)
    }

    fn answers(&self, addr: u8, ep: usize) -> bool {
        self.pulled_up() && self.enumerated && addr == self.addr && ep < EPS
    }

    /// The token after a SETUP queues its "setup stage done".
    fn end_setup_stage(&mut self) {
        if std::mem::take(&mut self.setup_stage) {
            let room = self.rx_words() as usize;
            if !self.rx.push(status(0, 0, SETUP_DONE, self.frame), &[], room) {
                crate::unmodelled("OTG_FS RX FIFO full at the end of a SETUP stage");
            }
        }
    }

    /// A SETUP transaction to `addr`, EP0.
    pub fn setup(&mut self, addr: u8, data: [u8; 8]) -> Handshake {
        if !self.answers(addr, 0) {
            return Handshake::Timeout;
        }
        self.check_layout(None);
        self.setup_stage = false;
        let room = self.rx_words() as usize;
        if !self.rx.push(status(0, 8, SETUP_DATA, self.frame), &data, room) {
            crate::unmodelled("OTG_FS RX FIFO without room for a SETUP packet (§22.11.1 reserves it)");
        }
        let o = &mut self.outs[0];
        let stupcnt = (o.siz >> 29 & 3).saturating_sub(1);
        o.siz = o.siz & !(3 << 29) | stupcnt << 29;
        for e in [&mut self.outs[0], &mut self.ins[0]] {
            e.ctl = e.ctl & !STALL | NAKSTS;
        }
        self.setup_stage = true;
        Handshake::Ack
    }

    /// An OUT transaction of `data` to endpoint `ep` at `addr`.
    pub fn out(&mut self, addr: u8, ep: usize, data: &[u8]) -> Handshake {
        if !self.answers(addr, ep) || (ep != 0 && !self.outs[ep].has(USBAEP)) {
            return Handshake::Timeout;
        }
        if ep == 0 {
            self.end_setup_stage();
        }
        let e = self.outs[ep];
        if e.has(STALL) {
            return Handshake::Stall;
        }
        let mps = e.mps(ep);
        if e.has(NAKSTS) || data.len() > mps {
            return Handshake::Nak;
        }
        self.check_layout(None);
        // §22.11.1: SETUP_RESERVE words of the RX FIFO are kept for SETUP
        // packets; the core never writes other data into them
        let room = self.rx_words() as usize;
        let done_room = usize::from(e.pktcnt() <= 1 || data.len() < mps);
        if self.rx.words() + data.len().div_ceil(4) + 1 + done_room + SETUP_RESERVE > room {
            return Handshake::Nak;
        }
        self.rx.push(status(ep, data.len(), OUT_DATA, self.frame), data, room);
        if self.outs[ep].count(data.len(), mps) {
            self.outs[ep].ctl |= NAKSTS;
            self.rx.push(status(ep, 0, OUT_DONE, self.frame), &[], room);
        }
        Handshake::Ack
    }

    /// An IN token to endpoint `ep` at `addr`.
    pub fn in_token(&mut self, addr: u8, ep: usize) -> InReply {
        if !self.answers(addr, ep) || (ep != 0 && !self.ins[ep].has(USBAEP)) {
            return InReply::Timeout;
        }
        if ep == 0 {
            self.end_setup_stage();
        }
        let e = self.ins[ep];
        if e.has(STALL) {
            return InReply::Stall;
        }
        if !e.has(EPENA) || e.has(NAKSTS) {
            return InReply::Nak;
        }
        let len = (e.xfrsiz() as usize).min(e.mps(ep));
        let f = self.fifo_of(ep);
        let Some(packet) = self.tx[f].take(len) else { return InReply::Nak };
        if self.ins[ep].count(len, e.mps(ep)) && self.ins[ep].pktcnt() == 0 {
            self.ins[ep].ctl &= !EPENA;
            self.ins[ep].int |= XFRC;
            if ep == 0 {
                self.addr = (self.regs.get(DCFG) >> 4 & 0x7F) as u8;
            }
        }
        InReply::Data(packet)
    }

    /// GRXSTSP (§22.16.2): pops a status; popping "OUT transfer completed" raises
    /// DOEPINT.XFRC and disables the endpoint, "setup stage done" raises STUP.
    pub(super) fn pop_status(&mut self) -> u32 {
        let s = self.rx.status(true);
        let ep = (s & 0xF) as usize % EPS;
        match s >> 17 & 0xF {
            OUT_DONE => {
                self.outs[ep].int |= XFRC;
                self.outs[ep].ctl &= !EPENA;
            }
            // DOEPCTLx.EPENA (§22.16.4): the core clears it before it sets
            // SETUP phase done, endpoint disabled or transfer completed
            SETUP_DONE => {
                self.outs[0].int |= STUP;
                self.outs[0].ctl &= !EPENA;
            }
            _ => {}
        }
        s
    }
}
