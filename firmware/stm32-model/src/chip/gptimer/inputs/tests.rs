//! Input capture, the compare pulse and TRC, each against the sentence it models.

use super::super::GpTimer;
use crate::addr::off::{CCER, CCMR1, CCMR2, CCR1, CNT, CR1, CR2, EGR, PSC, SMCR, SR};
use crate::bits::{ccer, ccmr, ccmr_in, cr2, smcr, sr};
use crate::EncoderCapture;

const MHZ96: u64 = 96_000_000;
/// (A, B) through one cycle of table 53 counting up: A rises first, while B is low.
const UP: [[bool; 2]; 4] = [[true, false], [true, true], [false, true], [false, false]];

/// TIM3 as the board has it: encoder mode 3, channels 1 and 2 inputs on TI1 and TI2,
/// capture enabled on both, rising edges; MMS as given.
fn encoder(capture: EncoderCapture, mms: u32) -> GpTimer {
    let mut t = GpTimer::new(16, 4);
    t.set_encoder_capture(capture);
    t.write(SMCR, smcr::SMS.val(smcr::SMS_ENCODER_3), u32::MAX);
    t.write(CCMR1, ccmr::ccs(0).val(ccmr_in::CCS_TI) | ccmr::ccs(1).val(ccmr_in::CCS_TI), u32::MAX);
    t.write(CCER, ccer::cce(0).mask() | ccer::cce(1).mask(), u32::MAX);
    t.write(CR2, cr2::MMS.val(mms), u32::MAX);
    t.write(CR1, 1, u32::MAX);
    t
}

fn play(t: &mut GpTimer, steps: &[[bool; 2]]) {
    for ab in steps {
        t.inputs([ab[0], ab[1], false]);
    }
}

#[test]
fn a_rise_of_a_latches_the_count_before_or_after_its_own_count_as_the_reading_says() {
    for (capture, up, down) in [(EncoderCapture::CountBefore, 4, 7), (EncoderCapture::CountAfter, 5, 6)] {
        let mut t = encoder(capture, 0);
        play(&mut t, &UP); // 0 -> 4
        play(&mut t, &UP[..1]); // A rises counting up: 4 -> 5
        assert_eq!(t.read(CCR1), up, "{capture:?} up");
        play(&mut t, &UP[1..]); // 5 -> 8
                                // counting down from (0,0): B rises (7), A rises (6): table 53, TI2 high
        play(&mut t, &[[false, true], [true, true]]);
        assert_eq!(t.read(CNT), 6);
        assert_eq!(t.read(CCR1), down, "{capture:?} down");
    }
}

#[test]
fn a_falling_a_or_a_channel_not_enabled_captures_nothing() {
    let mut t = encoder(EncoderCapture::CountBefore, 0);
    t.write(CCER, ccer::cce(1).mask(), u32::MAX); // CC1E = 0: "capture disabled"
    play(&mut t, &UP);
    play(&mut t, &UP[..1]);
    assert_eq!((t.read(SR) & sr::ccif(0).mask(), t.read(CCR1)), (0, 0));
    t.write(CCER, ccer::cce(0).mask(), u32::MAX);
    play(&mut t, &UP[1..3]); // B rises, A falls
    assert_eq!(t.read(SR) & sr::ccif(0).mask(), 0, "a falling TI1 is not the active edge");
}

#[test]
fn reading_ccr1_clears_cc1if_and_two_unread_captures_set_cc1of() {
    let mut t = encoder(EncoderCapture::CountBefore, 0);
    play(&mut t, &UP);
    assert_eq!(t.read(SR) & (sr::ccif(0).mask() | sr::ccof(0).mask()), sr::ccif(0).mask());
    play(&mut t, &UP);
    assert!(sr::ccof(0).on(t.read(SR)), "§13.4.5 CC1OF: captured while CC1IF was set");
    assert_eq!(t.read(CCR1), 4);
    assert!(!sr::ccif(0).on(t.read(SR)), "§13.4.5: cleared by reading TIMx_CCR1");
    assert!(sr::ccof(0).on(t.read(SR)), "CC1OF is cleared only by writing 0");
}

#[test]
fn trgo_pulses_at_every_cc1_capture_with_mms_011_only() {
    let mut t = encoder(EncoderCapture::CountBefore, cr2::MMS_COMPARE_PULSE);
    play(&mut t, &UP);
    play(&mut t, &UP);
    assert_eq!(t.take_trgo(), 2, "even with CC1IF already high");
    assert_eq!(t.take_trgo(), 0);
    let mut quiet = encoder(EncoderCapture::CountBefore, cr2::MMS_RESET);
    play(&mut quiet, &UP);
    assert_eq!(quiet.take_trgo(), 0);
}

#[test]
fn an_output_compare_match_on_channel_1_pulses_trgo_too() {
    let mut t = GpTimer::new(16, 4);
    t.write(crate::addr::off::ARR, 99, u32::MAX);
    t.write(CCR1, 10, u32::MAX);
    t.write(CR2, cr2::MMS.val(cr2::MMS_COMPARE_PULSE), u32::MAX);
    t.write(CR1, 1, u32::MAX);
    t.advance(20, MHZ96, MHZ96);
    assert_eq!(t.take_trgo(), 1, "\"as soon as a capture or a compare match occurred\"");
}

/// TIM5 as the board has it: 1 MHz (PSC 95), channel 3 on TRC from ITR1, enabled.
fn stamper() -> GpTimer {
    let mut t = GpTimer::new(32, 4);
    t.write(PSC, 95, u32::MAX);
    t.write(crate::addr::off::ARR, 0xFFFF, u32::MAX);
    t.write(EGR, 1, u32::MAX);
    t.write(SMCR, smcr::TS.val(smcr::TS_ITR1), u32::MAX);
    t.write(CCMR2, ccmr::ccs(0).val(ccmr_in::CCS_TRC), u32::MAX);
    t.write(CCER, ccer::cce(2).mask(), u32::MAX);
    t.write(CR1, 1, u32::MAX);
    t
}

#[test]
fn a_trc_channel_captures_cnt_at_a_pulse_of_the_selected_itr_only() {
    let mut t = stamper();
    t.advance(96 * 1234 + 50, MHZ96, MHZ96);
    t.trigger(0);
    t.trigger(2);
    assert_eq!(t.read(SR) & sr::ccif(2).mask(), 0, "TS = 001: ITR0 and ITR2 are not TRGI");
    t.trigger(1);
    assert_eq!(t.read(SR) & sr::ccif(2).mask(), sr::ccif(2).mask());
    assert_eq!(t.read(CCR1 + 8), 1234, "CCR3 = CNT at the pulse");
    assert_eq!(t.read(SR) & sr::ccif(2).mask(), 0, "read clears CC3IF");
    t.write(CCER, 0, u32::MAX);
    t.advance(96 * 2000, MHZ96, MHZ96);
    t.trigger(1);
    assert_eq!(t.read(CCR1 + 8), 1234, "CC3E = 0: no capture");
}

#[test]
fn the_trc_channel_leaves_the_counter_and_the_other_channels_alone() {
    let (mut t, mut plain) = (stamper(), stamper());
    plain.write(CCER, 0, u32::MAX);
    for k in 1..50 {
        t.advance(k * 1000, MHZ96, MHZ96);
        plain.advance(k * 1000, MHZ96, MHZ96);
        t.trigger(1);
        assert_eq!(t.read(CNT), plain.read(CNT), "SMS = 000: TRGI neither resets, gates nor clocks");
    }
    assert_eq!(t.read(SR) & !(sr::ccif(2).mask() | sr::ccof(2).mask()), plain.read(SR));
}
