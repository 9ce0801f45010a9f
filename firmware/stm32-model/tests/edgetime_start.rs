//! The start's measurements (`polyturn_firmware::edgetime::start`) on the
//! models: TIM11 (the `Mcu`'s, cycle-exact) started from TIM5's step, its
//! updates, the ticks' instants, on the stamps the firmware computes.

mod edge_board;

use edge_board::{Board, ACCESS};
use polyturn_firmware::board::TICK_HZ;
use polyturn_firmware::clocks::CLOCKS;
use polyturn_firmware::edgetime::{start, STAMPS_PER_TICK};
use polyturn_firmware::regs::Bus;
use polyturn_stm32_model::addr::{off, TIM11};
use polyturn_stm32_model::EncoderCapture;

/// TIM11's cycles a tick (APB2's timer clock).
const TICK_CYCLES: u64 = (CLOCKS.apb2_timer_hz() / TICK_HZ) as u64;

/// A board with TIM11 set up as `app::tick` does (PSC 0, ARR a tick's
/// cycles less one, UIE), stopped, at cycle `t`.
fn board(t: u64) -> Board {
    let mut b = Board::new(EncoderCapture::CountBefore);
    for (o, v) in [(off::PSC, 0), (off::ARR, TICK_CYCLES as u32 - 1), (off::DIER, 1)] {
        b.write(TIM11 + o, v);
    }
    b.run_to(t);
    b
}

/// Runs to TIM11's next update event and returns TIM5's count then.
fn next_update(b: &mut Board) -> u16 {
    let (updates, until) = (b.mcu.tim11_updates(), b.now + 2 * TICK_CYCLES);
    while b.mcu.tim11_updates() == updates && b.now < until {
        b.run_to(b.now + 1);
    }
    b.stamp_now()
}

#[test]
fn the_first_tick_comes_a_ticks_stamps_after_the_stamp_the_start_returns() {
    for phase in (0..96).step_by(7) {
        let mut b = board(1_000_000 + phase);
        let s = start::start_tick(&mut b).expect("TIM5 steps");
        assert_eq!(next_update(&mut b), s.wrapping_add(STAMPS_PER_TICK), "phase {phase}: the first update's stamp");
        assert!(b.now > ACCESS);
    }
}

/// Ticks lost (a flash erase): measured again with TIM11 running, at any
/// moment of its period, the next tick's instant is the stamp of the update
/// that tick answers: the next one, or with UIF set the one before.
#[test]
fn after_lost_ticks_the_next_instant_is_the_stamp_of_the_update_the_next_tick_answers() {
    let mut b = board(1_000_000);
    start::start_tick(&mut b).expect("TIM5 steps");
    let mut seen_pending = false;
    for k in 0..60u64 {
        b.run_to(b.now + 2_000 + 997 * k % TICK_CYCLES);
        let measured = start::next_instant(&mut b).expect("a try works");
        // the tick the core runs next answers the pending update, if any
        // (set before or during the measurement), else the next one
        let pending = b.read(TIM11 + off::SR) & 1 == 1;
        let next = next_update(&mut b);
        let answers = if pending { next.wrapping_sub(STAMPS_PER_TICK) } else { next };
        assert_eq!(measured, answers, "{k}: pending {pending}");
        seen_pending |= pending;
        b.write(TIM11 + off::SR, 0); // the tick answered it
    }
    assert!(seen_pending, "both cases met");
}
