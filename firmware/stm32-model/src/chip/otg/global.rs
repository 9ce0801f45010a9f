//! The global and device-wide registers (§22.16.2, §22.16.4, §22.16.5).

use super::{reg::*, Otg, RegFile, EPS, FIFO_WORDS};
use crate::unmodelled;

/// GINTSTS flags the application clears by writing 1 (rc_w1, §22.16.2 GINTSTS):
/// MMIS, SOF, ESUSP, USBSUSP, USBRST, ENUMDNE, ISOODRP, EOPF, IISOIXFR,
/// IPXFR, CIDSCHG, DISCINT, SRQINT, WKUPINT.
pub const RC_W1: u32 = 0xF030_FC0A;
pub const SOF: u32 = 1 << 3;
pub const RXFLVL: u32 = 1 << 4;
pub const USBRST: u32 = 1 << 12;
pub const ENUMDNE: u32 = 1 << 13;
pub const EOPF: u32 = 1 << 15;
pub const IEPINT: u32 = 1 << 18;
pub const OEPINT: u32 = 1 << 19;
/// NPTXFE and PTXFE: host-mode status, reading as at reset (§22.16.2 GINTSTS).
const HOST_FIFO_EMPTY: u32 = 0x0400_0020;
/// GRSTCTL (§22.16.2): CSRST, HSRST, FCRST, RXFFLSH, TXFFLSH, TXFNUM, AHBIDL
const CSRST: u32 = 1 << 0;
/// HSRST (the HCLK soft reset) and FCRST (host mode's frame counter reset)
const OTHER_RESETS: u32 = 0b110;
const RXFFLSH: u32 = 1 << 4;
const TXFFLSH: u32 = 1 << 5;
const AHBIDL: u32 = 1 << 31;
/// GUSBCFG.FHMOD (§22.16.2): host mode, not modelled
const FHMOD: u32 = 1 << 29;
/// DCTL (§22.16.4): SDIS, and the global NAK commands SGINAK..CGONAK
pub const SDIS: u32 = 1 << 1;
const GLOBAL_NAK: u32 = 0xF << 7;
/// GCCFG (§22.16.2): PWRDWN (transceiver on), NOVBUSSENS
pub const PWRDWN: u32 = 1 << 16;
pub const NOVBUSSENS: u32 = 1 << 21;

/// Plain read/write registers with their reset values (§22.16.2-§22.16.5).
const PLAIN: &[(u32, u32)] = &[
    (GOTGCTL, 0x0000_0800),
    (GOTGINT, 0),
    (GAHBCFG, 0),
    (GUSBCFG, 0x0000_0A00),
    (GINTMSK, 0),
    (GRXFSIZ, 0x0000_0200),
    (DIEPTXF0, 0x0000_0200),
    (GCCFG, 0),
    (HPTXFSIZ, 0x0200_0600),
    (DIEPTXF1, 0x0200_0400),
    (DIEPTXF1 + 4, 0x0200_0400),
    (DIEPTXF1 + 8, 0x0200_0400),
    (DCFG, 0x0220_0000),
    (DCTL, 0),
    (DIEPMSK, 0),
    (DOEPMSK, 0),
    (DAINTMSK, 0),
    (DVBUSDIS, 0x0000_17D7),
    (DVBUSPULSE, 0x0000_05B8),
    (DIEPEMPMSK, 0),
    (PCGCCTL, 0),
];

pub fn reset_regs() -> RegFile {
    RegFile::new(PLAIN)
}

impl Otg {
    pub(super) fn global_read(&mut self, off: u32) -> u32 {
        match off {
            GRSTCTL => AHBIDL,
            GINTSTS => self.gintsts(),
            GRXSTSR => self.rx.status(false),
            GRXSTSP => self.pop_status(),
            CID => 0x0000_1200,
            GHWCFG4 => 0,
            DSTS => self.dsts(),
            DAINT => self.daint(),
            _ if PLAIN.iter().any(|p| p.0 == off) => self.regs.get(off),
            _ => unmodelled(&format!("read of OTG_FS offset {off:#x}")),
        }
    }

    pub(super) fn global_write(&mut self, off: u32, v: u32) {
        match off {
            GRSTCTL => self.grstctl(v),
            GINTSTS => self.flags &= !(v & RC_W1),
            GOTGINT => self.regs.set(off, self.regs.get(off) & !v),
            GUSBCFG if v & FHMOD != 0 => unmodelled("OTG_FS host mode (GUSBCFG.FHMOD)"),
            DCTL if v & GLOBAL_NAK != 0 => unmodelled("OTG_FS global NAK commands (DCTL bits 7-10)"),
            GRXSTSR | GRXSTSP | CID | DSTS | DAINT => {} // read-only
            _ if PLAIN.iter().any(|p| p.0 == off) => self.regs.set(off, v),
            _ => unmodelled(&format!("write {v:#x} to OTG_FS offset {off:#x}")),
        }
    }

    /// GINTSTS (§22.16.2): the latched flags, CMOD = 0 (device mode: the ID pin
    /// unconnected reads as a B-device, §22.4), RXFLVL while the RX FIFO holds a
    /// status, IEPINT/OEPINT from DAINT & DAINTMSK, OTGINT from GOTGINT.
    pub fn gintsts(&self) -> u32 {
        let daint = self.daint() & self.regs.get(DAINTMSK);
        let mut s = self.flags | HOST_FIFO_EMPTY;
        s |= if self.rx.pending() { RXFLVL } else { 0 };
        s |= if daint & 0xFFFF != 0 { IEPINT } else { 0 };
        s |= if daint >> 16 != 0 { OEPINT } else { 0 };
        s |= if self.regs.get(GOTGINT) != 0 { 1 << 2 } else { 0 };
        s
    }

    /// DAINT (§22.16.4): bit n (IN) / 16 + n (OUT) while endpoint n has an
    /// interrupt its mask (DIEPMSK, DIEPEMPMSK for TXFE; DOEPMSK) lets through.
    pub fn daint(&self) -> u32 {
        let (im, om, em) = (self.regs.get(DIEPMSK), self.regs.get(DOEPMSK), self.regs.get(DIEPEMPMSK));
        (0..EPS).fold(0, |acc, n| {
            let txfe = if em >> n & 1 != 0 { ep_txfe() } else { 0 };
            let i = self.diepint(n) & (im | txfe) != 0;
            let o = self.outs[n].int & om != 0;
            acc | (i as u32) << n | (o as u32) << (16 + n)
        })
    }

    /// DSTS (§22.16.4): ENUMSPD = 11 (full speed, 48 MHz PHY clock) once
    /// enumerated, FNSOF the frame number of the last SOF.
    fn dsts(&self) -> u32 {
        let spd = if self.enumerated { 0b11 << 1 } else { 0 };
        spd | (self.frame as u32 & 0x3FFF) << 8 | 0x10
    }

    /// GRSTCTL (§22.16.2): RXFFLSH/TXFFLSH flush the RX FIFO / the TX FIFO
    /// TXFNUM (0x10: all). CSRST is refused: the manual has it clear the
    /// interrupts and the control and status registers but a few named bits,
    /// which this model does not list, and the firmware (embassy-stm32's OTG
    /// init) never asks for it.
    fn grstctl(&mut self, v: u32) {
        if v & OTHER_RESETS != 0 {
            unmodelled("OTG_FS GRSTCTL HSRST/FCRST");
        }
        if v & CSRST != 0 {
            unmodelled("OTG_FS core soft reset (GRSTCTL.CSRST)");
        }
        if v & RXFFLSH != 0 {
            self.rx.clear();
        }
        if v & TXFFLSH != 0 {
            let n = (v >> 6 & 0x1F) as usize;
            for (i, f) in self.tx.iter_mut().enumerate() {
                if n == 0x10 || n == i {
                    f.clear();
                }
            }
        }
    }

    /// The TX FIFO sizes and starts (§22.16.2 DIEPTXF0, DIEPTXFx) in words.
    pub(super) fn tx_fifo(&self, n: usize) -> (u32, u32) {
        let r = if n == 0 { self.regs.get(DIEPTXF0) } else { self.regs.get(DIEPTXF1 + 4 * (n as u32 - 1)) };
        (r & 0xFFFF, r >> 16)
    }

    /// §22.13, checked when FIFO `n` (None: the RX FIFO) takes data: the RX FIFO
    /// from word 0, at least 16 words (§22.16.2 GRXFSIZ); the TX FIFO in use at
    /// least 16 words (DIEPTXFx) and within the 320; no overlap with the RX FIFO or
    /// another TX FIFO placed within the 320 (one still at its reset place, past
    /// the RAM, is taken as unused).
    pub(super) fn check_layout(&self, n: Option<usize>) {
        let rxfd = self.rx_words();
        let mut spans = vec![(0, rxfd)];
        let placed =
            (0..EPS).map(|i| (i, self.tx_fifo(i))).filter(|(i, (sa, fd))| Some(*i) == n || sa + fd <= FIFO_WORDS);
        spans.extend(placed.map(|(_, (sa, fd))| (sa, sa + fd)));
        spans.sort();
        let overlap = spans.windows(2).any(|w| w[1].0 < w[0].1);
        if rxfd < 16 || overlap || spans.iter().any(|s| s.1 > FIFO_WORDS || s.1 - s.0 < 16) {
            unmodelled(&format!("OTG_FS FIFO layout {spans:?} (words): overlapping, under 16 or past 320"));
        }
    }

    /// The RX FIFO's size in words (GRXFSIZ.RXFD).
    pub(super) fn rx_words(&self) -> u32 {
        self.regs.get(GRXFSIZ) & 0xFFFF
    }

    /// The D+ pull-up (§22.5.2, §22.16.4 DCTL.SDIS): the transceiver on
    /// (GCCFG.PWRDWN), VBUS taken as present (NOVBUSSENS, no VBUS pin here) and
    /// no soft disconnect.
    pub fn pulled_up(&self) -> bool {
        let gccfg = self.regs.get(GCCFG);
        gccfg & PWRDWN != 0 && gccfg & NOVBUSSENS != 0 && self.regs.get(DCTL) & SDIS == 0
    }
}

/// DIEPINT.TXFE (bit 7).
fn ep_txfe() -> u32 {
    1 << 7
}
