//! The bus-side statements of `wire`, each with its section.

use super::ep::{CNAK, EPENA, NAKSTS, STALL, STUP, USBAEP, XFRC};
use super::reg::*;
use super::tests::{device, panics, w};
use super::{Handshake, InReply, Otg};

const GET_DEVICE: [u8; 8] = [0x80, 6, 0, 1, 0, 0, 18, 0];

fn pop(o: &mut Otg) -> (u32, u32, u32) {
    let s = o.read(GRXSTSP);
    (s & 0xF, s >> 4 & 0x7FF, s >> 17 & 0xF)
}

#[test]
fn a_setup_is_always_taken_and_its_stage_done_raises_stup_22_17_6() {
    let mut o = device();
    w(&mut o, DOEPTSIZ0, 3 << 29);
    w(&mut o, DIEPCTL, STALL);
    assert_eq!(o.setup(0, GET_DEVICE), Handshake::Ack);
    assert_ne!(o.read(GINTSTS) & 1 << 4, 0, "RXFLVL");
    assert_eq!(pop(&mut o), (0, 8, 0b0110));
    assert_eq!(o.read(FIFO).to_le_bytes(), [0x80, 6, 0, 1]);
    assert_eq!(o.read(FIFO + 0x3000).to_le_bytes(), [0, 0, 18, 0], "any window reads the RX FIFO");
    assert_eq!(o.read(GINTSTS) & 1 << 4, 0);
    assert_eq!(o.read(DOEPTSIZ0) >> 29, 2, "STUPCNT");
    assert_eq!(o.read(DIEPCTL) & (STALL | NAKSTS), NAKSTS, "STALL cleared, NAK set");
    assert_eq!(o.in_token(0, 0), InReply::Nak, "the data stage begins");
    assert_eq!(pop(&mut o), (0, 0, 0b0100));
    assert_eq!(o.read(DOEPCTL + 8), STUP);
    w(&mut o, DOEPMSK, STUP);
    w(&mut o, DAINTMSK, 1 << 16);
    assert_ne!(o.read(GINTSTS) & 1 << 19, 0, "OEPINT");
}

const DOEPTSIZ0: u32 = DOEPCTL + 0x10;

#[test]
fn an_in_packet_goes_once_whole_in_the_fifo_22_17_6() {
    let mut o = device();
    w(&mut o, DIEPCTL + 0x10, 1 << 19 | 6);
    w(&mut o, DIEPCTL, CNAK | EPENA);
    assert_eq!(o.in_token(0, 0), InReply::Nak, "nothing written yet");
    w(&mut o, FIFO, u32::from_le_bytes(*b"poly"));
    assert_eq!(o.in_token(0, 0), InReply::Nak, "half a packet");
    w(&mut o, FIFO, u32::from_le_bytes(*b"tu\0\0"));
    assert_eq!(o.in_token(0, 0), InReply::Data(b"polytu".to_vec()));
    assert_eq!(o.read(DIEPCTL) & EPENA, 0);
    assert_eq!(o.read(DIEPCTL + 8) & XFRC, XFRC);
    assert_eq!(o.in_token(0, 0), InReply::Nak, "disabled again");
}

#[test]
fn a_zero_length_packet_22_17_6() {
    let mut o = device();
    w(&mut o, DIEPCTL + 0x10, 1 << 19);
    w(&mut o, DIEPCTL, CNAK | EPENA);
    assert_eq!(o.in_token(0, 0), InReply::Data(vec![]));
}

#[test]
fn out_data_waits_for_cnak_and_completes_22_17_6() {
    let mut o = device();
    let c = DOEPCTL + 0x20;
    w(&mut o, c, USBAEP | 64 | 2 << 18 | SNAKED);
    w(&mut o, c + 0x10, 1 << 19 | 64);
    assert_eq!(o.out(0, 1, b"status\n"), Handshake::Nak);
    let v = o.read(c);
    w(&mut o, c, v | CNAK | EPENA);
    assert_eq!(o.out(0, 1, b"status\n"), Handshake::Ack);
    assert_eq!(o.read(c) & NAKSTS, NAKSTS, "the core NAKs after the transfer");
    assert_eq!(o.out(0, 1, b"more"), Handshake::Nak);
    assert_eq!(pop(&mut o), (1, 7, 0b0010));
    assert_eq!(o.read(FIFO).to_le_bytes(), *b"stat");
    assert_eq!(o.read(FIFO).to_le_bytes(), *b"us\n\0");
    assert_eq!(pop(&mut o), (1, 0, 0b0011));
    assert_eq!(o.read(c + 8), XFRC);
    assert_eq!(o.read(c) & EPENA, 0);
    let v = o.read(c);
    w(&mut o, c, v | CNAK);
    assert_eq!(o.out(0, 1, b"more"), Handshake::Ack, "CNAK alone re-arms (as on silicon)");
}

const SNAKED: u32 = 1 << 27;

#[test]
fn a_full_rx_fifo_naks_22_11_1() {
    let mut o = device();
    let c = DOEPCTL + 0x20;
    w(&mut o, c, USBAEP | 64 | 2 << 18 | CNAK);
    w(&mut o, c + 0x10, 3 << 19 | 192);
    // 46 words hold two 64-byte packets with their status words, not three
    assert_eq!(o.out(0, 1, &[0; 64]), Handshake::Ack);
    assert_eq!(o.out(0, 1, &[0; 64]), Handshake::Ack);
    assert_eq!(o.out(0, 1, &[0; 64]), Handshake::Nak);
    assert_eq!(pop(&mut o), (1, 64, 0b0010));
    for _ in 0..16 {
        o.read(FIFO);
    }
    assert_eq!(o.out(0, 1, &[0; 64]), Handshake::Ack, "room again");
}

#[test]
fn out_data_leaves_the_setup_reserve_so_a_setup_is_always_taken_22_11_1() {
    let mut o = device();
    let c = DOEPCTL + 0x20;
    w(&mut o, c, USBAEP | 64 | 2 << 18 | CNAK);
    w(&mut o, c + 0x10, 7 << 19 | 448);
    // 46 words less the 10 kept for SETUP: two 64-byte packets (17 words
    // each with their status) fit; a 36-byte one that ends the transfer
    // (9 words, its status and the "completed" word) would reach into it
    for _ in 0..2 {
        assert_eq!(o.out(0, 1, &[0; 64]), Handshake::Ack);
    }
    assert_eq!(o.out(0, 1, &[0; 36]), Handshake::Nak);
    assert_eq!(o.setup(0, GET_DEVICE), Handshake::Ack, "the reserve holds the SETUP");
}

#[test]
fn the_setup_stage_done_pop_disables_out0_22_16_4() {
    let mut o = device();
    w(&mut o, DOEPTSIZ0, 3 << 29);
    w(&mut o, DOEPCTL, EPENA | CNAK);
    o.setup(0, GET_DEVICE);
    pop(&mut o);
    o.read(FIFO);
    o.read(FIFO);
    assert_eq!(o.in_token(0, 0), InReply::Nak);
    assert_eq!(pop(&mut o), (0, 0, 0b0100));
    assert_eq!(o.read(DOEPCTL + 8) & STUP, STUP);
    assert_eq!(o.read(DOEPCTL) & EPENA, 0, "EPENA cleared before STUP");
}

#[test]
fn stall_answers_until_cleared_22_16_4() {
    let mut o = device();
    w(&mut o, DIEPCTL, STALL);
    w(&mut o, DOEPCTL, STALL);
    assert_eq!(o.in_token(0, 0), InReply::Stall);
    assert_eq!(o.out(0, 0, &[]), Handshake::Stall);
    assert_eq!(o.setup(0, GET_DEVICE), Handshake::Ack, "SETUP is taken regardless");
    assert_eq!(o.read(DOEPCTL) & STALL, 0);
}

#[test]
fn the_address_applies_after_the_status_stage() {
    let mut o = device();
    o.setup(0, [0, 5, 7, 0, 0, 0, 0, 0]);
    w(&mut o, DCFG, 7 << 4);
    w(&mut o, DIEPCTL + 0x10, 1 << 19);
    w(&mut o, DIEPCTL, CNAK | EPENA);
    assert_eq!(o.in_token(7, 0), InReply::Timeout, "not yet");
    assert_eq!(o.in_token(0, 0), InReply::Data(vec![]));
    assert_eq!(o.in_token(0, 0), InReply::Timeout);
    assert_eq!(o.in_token(7, 0), InReply::Nak);
}

#[test]
fn no_answer_unplugged_unreset_or_inactive() {
    let mut o = device();
    assert_eq!(o.out(0, 1, &[1]), Handshake::Timeout, "EP1 not active");
    w(&mut o, DCTL, 1 << 1);
    assert_eq!(o.setup(0, GET_DEVICE), Handshake::Timeout, "soft disconnect");
    assert_eq!(Otg::default().in_token(0, 0), InReply::Timeout);
}

#[test]
fn reset_enumeration_and_frames_22_15() {
    let mut o = device();
    w(&mut o, GINTSTS, u32::MAX);
    w(&mut o, DIEPCTL + 0x20, USBAEP | 64);
    o.bus_reset();
    assert_eq!(o.read(GINTSTS) & (1 << 12 | 1 << 13), 1 << 12, "USBRST");
    assert_eq!(o.read(DIEPCTL + 0x20) & USBAEP, 0, "EP1 deactivated");
    o.reset_done();
    assert_eq!(o.read(DSTS) >> 1 & 3, 3, "ENUMSPD full speed");
    o.sof(0x123);
    assert_eq!(o.read(DSTS) >> 8 & 0x3FFF, 0x123);
    assert_ne!(o.read(GINTSTS) & 1 << 3, 0, "SOF");
    o.end_of_periodic_frame();
    assert_ne!(o.read(GINTSTS) & 1 << 15, 0, "EOPF");
    assert_eq!(o.periodic_frame_percent(), 80);
}

#[test]
fn reading_status_before_the_data_is_refused_22_16_2() {
    let mut o = device();
    o.setup(0, GET_DEVICE);
    o.in_token(0, 0);
    pop(&mut o);
    assert!(panics(|| {
        let _ = o.read(GRXSTSR);
    })
    .contains("before the last packet's data"));
}
