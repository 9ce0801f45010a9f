//! The firmware's edge-time configuration (`polyturn_firmware::edgetime`),
//! applied verbatim to the models of TIM3 and TIM5 (RM0383 §13.3.5 capture,
//! §13.4.2 compare pulse, §13.4.3 ITR1): a quadrature signal at a known speed,
//! read by the tick's own read, gives back the count and the µs of A's last
//! rise, whichever count the capture takes (`EncoderCapture`).

mod edge_board;

use edge_board::{levels, Board};
use polyturn_firmware::edgetime::read::{lathe, Gate};
use polyturn_firmware::edgetime::{off, start, TIM3};
use polyturn_firmware::regs::Bus;
use polyturn_stm32_model::EncoderCapture;
use polyturn_sync::edges::{boundary_half_counts, EdgeRegs};

/// 12 000 counts/s (300 rpm at 2 400 counts): a count every 8 000 cycles,
/// A rising every 32 000 cycles (333⅓ µs).
const COUNT_CYCLES: u64 = 8_000;
/// TIM11's cycles a tick (APB2's timer clock).
const TICK_CYCLES: u64 = (polyturn_firmware::clocks::CLOCKS.apb2_timer_hz() / polyturn_firmware::board::TICK_HZ) as u64;

/// A's last rise: its stamp and the counts either side of it.
#[derive(Clone, Copy)]
struct Rise {
    stamp: u16,
    from: i64,
    to: i64,
}

/// The tick's reads at cycle `t`: TIM3_SR (the gate), then `read::lathe`.
fn tick(b: &mut Board, gate: &mut Gate, t: u64) -> (u16, Option<EdgeRegs>) {
    b.run_to(t);
    let sr = b.read(TIM3 + off::SR);
    gate.note(sr);
    lathe(*gate, b)
}

/// 200 counts forward then 200 back, ticking every tick in between: every
/// tick's pair is A's last rise.
fn run(capture: EncoderCapture) -> Vec<Rise> {
    let mut b = Board::new(capture);
    let k0 = start::low_low(&mut b).unwrap();
    assert_eq!(k0, 0, "count 0 at rest in (0, 0)");
    let odd = start::clock(0, k0).low_low_odd;
    let (mut gate, mut count, mut rises) = (Gate::Waiting, 0i64, Vec::<Rise>::new());
    let (mut next_count, mut next_tick) = (100_000u64, 50_000u64);
    for k in 0..400 {
        let dir = if k < 200 { 1 } else { -1 };
        while next_tick < next_count {
            let (cnt, edge) = tick(&mut b, &mut gate, next_tick);
            assert_eq!(cnt as i64, count.rem_euclid(65_536));
            let want = rises.last().map(|r| {
                let latched = if capture == EncoderCapture::CountBefore { r.from } else { r.to };
                EdgeRegs { count: latched as u16, stamp: r.stamp }
            });
            assert_eq!(edge, want, "{capture:?}, tick at {next_tick}");
            if let Some(e) = edge {
                let r = rises.last().unwrap();
                assert_eq!(boundary_half_counts(e.count as i64, odd), r.from + r.to, "the edge's place");
            }
            next_tick += TICK_CYCLES;
        }
        let (a0, _) = levels(count);
        count += dir;
        let (a, bb) = levels(count);
        b.drive(next_count, a, bb);
        if a && !a0 {
            rises.push(Rise { stamp: b.stamp_now(), from: count - dir, to: count });
        }
        next_count += COUNT_CYCLES;
    }
    rises
}

#[test]
fn every_tick_reads_the_count_and_the_us_of_as_last_rise_either_way_the_capture_falls() {
    for capture in [EncoderCapture::CountBefore, EncoderCapture::CountAfter] {
        let rises = run(capture);
        assert_eq!(rises.len(), 100);
        for w in rises.windows(2).filter(|w| w[0].to > w[0].from && w[1].to > w[1].from) {
            let us = w[1].stamp.wrapping_sub(w[0].stamp);
            assert!((333..=334).contains(&us), "A's period is 333⅓ µs: {us}");
        }
    }
}

#[test]
fn a_capture_made_before_the_configuration_does_not_open_the_gate() {
    let mut b = Board::embassy(EncoderCapture::CountBefore);
    b.drive(10_000, true, false); // A rises: CC1 captures, no TRGO yet
    polyturn_firmware::regs::apply(&polyturn_firmware::edgetime::program::CONFIG, &mut b).unwrap();
    let mut gate = Gate::Waiting;
    assert_eq!(tick(&mut b, &mut gate, 20_000), (1, None));
    b.drive(30_000, true, true); // B rises: channel 2, no edge time
    b.drive(40_000, false, true);
    b.drive(50_000, false, false);
    assert_eq!(tick(&mut b, &mut gate, 60_000), (4, None));
    b.drive(70_000, true, false);
    let stamp = b.stamp_now();
    assert_eq!(tick(&mut b, &mut gate, 80_000), (5, Some(EdgeRegs { count: 4, stamp })));
}

#[test]
fn the_low_low_count_is_found_from_any_state() {
    let mut b = Board::new(EncoderCapture::CountBefore);
    b.write(TIM3 + off::CNT, 5); // (0, 0) is now count 5: k0 odd
    for (k, c) in (6..=7).enumerate() {
        let (a, bb) = levels(c - 5);
        b.drive(1_000 + 1_000 * k as u64, a, bb);
    }
    assert_eq!(start::low_low(&mut b), Some(5), "count 7 in (1, 1)");
}

/// Embassy's TIM5 interrupt is SR & DIER with UIE and CC1IE (CC2IE for its
/// alarm): the captures set CC3IF and CC3OF, which its DIER does not enable,
/// so they raise nothing, and its clear (SR = !SR, rc_w0) leaves CCR3.
#[test]
fn the_captures_raise_no_interrupt_of_embassys_timer() {
    let mut b = Board::new(EncoderCapture::CountBefore);
    let cc3 = 1 << 3 | 1 << 11;
    for (k, c) in (1..=8).enumerate() {
        let (a, bb) = levels(c);
        b.drive(10_000 * (k as u64 + 1), a, bb);
    }
    assert_eq!(b.tim5.get(off::SR) & cc3, cc3, "two captures unread: CC3IF and CC3OF");
    assert!(!b.tim5.irq(0xFF), "no TIM5 interrupt from a capture");
    let ccr3 = b.tim5.get(off::CCR3);
    let sr = b.tim5.read(off::SR);
    b.tim5.write(off::SR, !sr, u32::MAX);
    assert_eq!((b.tim5.get(off::SR) & cc3, b.tim5.get(off::CCR3)), (0, ccr3));
}
