//! The register statements of `otg`, `global` and `ep`, each with its section.

use super::ep::{CNAK, EPDIS, EPENA, SNAK, STALL, TXFE, USBAEP, XFRC};
use super::global::{NOVBUSSENS, PWRDWN, SDIS};
use super::reg::*;
use super::Otg;
use std::panic::{catch_unwind, AssertUnwindSafe};

pub fn w(o: &mut Otg, off: u32, v: u32) {
    o.write(off, v, u32::MAX);
}

/// A core as embassy leaves it: transceiver on, FIFOs placed (RX 46 words, TX0
/// and TX1 16 each), the bus reset and enumerated.
pub fn device() -> Otg {
    let mut o = Otg::default();
    w(&mut o, GCCFG, PWRDWN | NOVBUSSENS);
    w(&mut o, GRXFSIZ, 46);
    w(&mut o, DIEPTXF0, 16 << 16 | 46);
    w(&mut o, DIEPTXF1, 16 << 16 | 62);
    o.bus_reset();
    o.reset_done();
    o
}

pub fn panics(f: impl FnOnce()) -> String {
    let e = catch_unwind(AssertUnwindSafe(f)).expect_err("expected a not-modelled panic");
    e.downcast_ref::<String>().cloned().unwrap_or_default()
}

#[test]
fn reset_values_22_16() {
    let mut o = Otg::default();
    assert_eq!(o.read(GRSTCTL), 1 << 31, "AHBIDL");
    assert_eq!(o.read(GINTSTS), 0x0400_0020, "CMOD = 0: device mode");
    assert_eq!(o.read(CID), 0x1200);
    assert_eq!(o.read(GRXFSIZ), 0x200);
    assert_eq!(o.read(DCFG), 0x0220_0000);
    assert_eq!(o.read(DSTS), 0x10);
    assert_eq!(o.read(DOEPCTL) & USBAEP, USBAEP, "EP0 always active");
    assert_eq!(o.read(DIEPCTL + 8) & TXFE, TXFE, "an empty TX FIFO");
    assert!(!o.irq());
}

#[test]
fn gintsts_flags_clear_by_writing_1_22_16_2() {
    let mut o = device();
    assert_ne!(o.read(GINTSTS) & (1 << 12 | 1 << 13), 0);
    w(&mut o, GINTSTS, 1 << 12);
    assert_eq!(o.read(GINTSTS) & (1 << 12), 0);
    assert_ne!(o.read(GINTSTS) & (1 << 13), 0, "ENUMDNE stays");
    w(&mut o, GINTSTS, 0xFFFF_FFFF);
    assert_eq!(o.read(GINTSTS), 0x0400_0020);
}

#[test]
fn the_line_needs_gintmsk_and_gahbcfg_22_15() {
    let mut o = device();
    assert!(!o.irq(), "masked");
    w(&mut o, GINTMSK, 1 << 12);
    assert!(!o.irq(), "GAHBCFG.GINTMSK clear");
    w(&mut o, GAHBCFG, 1);
    assert!(o.irq());
    w(&mut o, GINTSTS, 1 << 12);
    assert!(!o.irq());
}

#[test]
fn what_is_not_modelled_panics() {
    assert!(panics(|| {
        let _ = Otg::default().read(0x40);
    })
    .contains("not modelled: read of OTG_FS offset 0x40"));
    assert!(panics(|| w(&mut Otg::default(), GUSBCFG, 1 << 29)).contains("host mode"));
    assert!(panics(|| w(&mut Otg::default(), DCTL, 1 << 7)).contains("global NAK"));
    assert!(panics(|| Otg::default().write(DCFG, 1, 0xFF)).contains("byte or halfword"));
    assert!(panics(|| {
        let _ = Otg::default().read(GRXSTSP);
    })
    .contains("RX FIFO empty"));
    assert!(panics(|| {
        let _ = Otg::default().read(FIFO);
    })
    .contains("no packet data"));
    assert!(panics(|| {
        let _ = Otg::default().read(DIEPCTL + 4 * 0x20);
    })
    .contains("endpoint 4"));
}

#[test]
fn soft_disconnect_drops_the_pull_up_22_16_4() {
    let mut o = Otg::default();
    assert!(!o.pulled_up(), "transceiver off");
    w(&mut o, GCCFG, PWRDWN | NOVBUSSENS);
    assert!(o.pulled_up());
    w(&mut o, DCTL, SDIS);
    assert!(!o.pulled_up());
}

#[test]
fn snak_cnak_and_epdis_22_16_4() {
    let mut o = device();
    let c = DIEPCTL + 0x20;
    w(&mut o, c, USBAEP | 64 | SNAK);
    assert_eq!(o.read(c), USBAEP | 64 | 1 << 17, "NAKSTS set, SNAK reads 0");
    let v = o.read(c);
    w(&mut o, c, v | CNAK | EPENA);
    assert_eq!(o.read(c), USBAEP | 64 | EPENA);
    let v = o.read(c);
    w(&mut o, c, v & !EPENA);
    assert_eq!(o.read(c) & EPENA, EPENA, "only the core clears EPENA");
    let v = o.read(c);
    w(&mut o, c, v | SNAK | EPDIS);
    assert_eq!(o.read(c) & (EPENA | EPDIS), 0);
    assert_eq!(o.read(DIEPCTL + 0x28) & 2, 2, "EPDISD");
    assert!(panics(|| w(&mut device(), c, SNAK | CNAK)).contains("SNAK and CNAK"));
}

#[test]
fn ep0_stall_is_set_only_by_software_22_16_4() {
    let mut o = device();
    w(&mut o, DIEPCTL, STALL);
    w(&mut o, DIEPCTL, 0);
    assert_eq!(o.read(DIEPCTL) & STALL, STALL);
    w(&mut o, DIEPCTL + 0x20, STALL);
    w(&mut o, DIEPCTL + 0x20, 0);
    assert_eq!(o.read(DIEPCTL + 0x20) & STALL, 0, "rw on the others");
}

#[test]
fn tx_fifo_space_flush_and_overrun_22_11_2() {
    let mut o = device();
    assert_eq!(o.read(DIEPCTL + 0x18), 16, "DTXFSTS: all 16 words free");
    for i in 0..10 {
        w(&mut o, FIFO, i);
    }
    assert_eq!(o.read(DIEPCTL + 0x18), 6);
    assert_eq!(o.read(DIEPCTL + 8) & TXFE, 0, "over half full");
    w(&mut o, GRSTCTL, 1 << 5); // TXFFLSH, TXFNUM 0
    assert_eq!(o.read(DIEPCTL + 0x18), 16);
    assert_eq!(o.read(GRSTCTL), 1 << 31, "the flush is done");
    for i in 0..16 {
        w(&mut o, FIFO, i);
    }
    assert!(panics(|| w(&mut o, FIFO, 0)).contains("overrun"));
}

#[test]
fn a_window_writes_the_fifo_txfnum_names_22_16_4() {
    let mut o = device();
    w(&mut o, DIEPCTL + 0x20, USBAEP | 64 | 1 << 22);
    w(&mut o, FIFO + 0x1000, 7);
    assert_eq!(o.read(DIEPCTL + 0x38), 15);
    assert_eq!(o.read(DIEPCTL + 0x18), 16, "FIFO 0 untouched");
}

#[test]
fn overlapping_fifos_are_refused_22_13() {
    let mut o = device();
    w(&mut o, DIEPTXF1, 16 << 16 | 40);
    w(&mut o, DIEPCTL + 0x20, USBAEP | 64 | 1 << 22);
    assert!(panics(|| w(&mut o, FIFO + 0x1000, 0)).contains("FIFO layout"));
}

#[test]
fn daint_and_the_endpoint_masks_22_16_4() {
    let mut o = device();
    o.ins[1].int = XFRC;
    assert_eq!(o.read(DAINT), 0, "DIEPMSK clear");
    w(&mut o, DIEPMSK, XFRC);
    assert_eq!(o.read(DAINT), 1 << 1);
    assert_eq!(o.read(GINTSTS) & (1 << 18), 0, "DAINTMSK clear");
    w(&mut o, DAINTMSK, 1 << 1);
    assert_ne!(o.read(GINTSTS) & (1 << 18), 0, "IEPINT");
    w(&mut o, DIEPCTL + 0x28, XFRC);
    assert_eq!(o.read(DAINT), 0);
    w(&mut o, DIEPEMPMSK, 1);
    assert_eq!(o.read(DAINT), 1, "TXFE of EP0, unmasked by DIEPEMPMSK");
}

#[test]
fn a_core_soft_reset_is_refused_not_guessed_22_16_2() {
    let mut o = device();
    assert!(panics(|| w(&mut o, GRSTCTL, 1)).contains("CSRST"));
}
