//! TIM1 time base, repetition counter and update events: one test per manual statement.
mod common;
use common::*;

// §12.3.1: "Note that the actual counter enable signal CNT_EN is set 1 clock cycle
// after CEN."
#[test]
fn counter_starts_counting_one_cycle_after_cen() {
    let mut m = mcu();
    m.write(TIM1_ARR, 100);
    start_tim1(&mut m, 0);
    assert_eq!(cnt_trace(&mut m, 4), [0, 1, 2, 3]);
}

// §12.3.2 "Upcounting mode": counts from 0 to ARR, restarts from 0 and generates an
// overflow, which sets UIF (§12.4.5).
#[test]
fn upcounter_counts_to_arr_then_restarts_from_zero_with_update() {
    let mut m = mcu();
    m.write(TIM1_ARR, 3);
    start_tim1(&mut m, 0);
    assert_eq!(cnt_trace(&mut m, 4), [0, 1, 2, 3]);
    assert!(!uif1(&mut m));
    assert_eq!(cnt_trace(&mut m, 3), [0, 1, 2]);
    assert!(uif1(&mut m));
}

// §12.3.1 "Prescaler description": "The new prescaler ratio is taken into account at the
// next update event."
#[test]
fn new_prescaler_ratio_is_taken_at_the_next_update_event() {
    let mut m = mcu();
    m.write(TIM1_ARR, 3);
    m.write(TIM1_PSC, 2);
    start_tim1(&mut m, 0);
    assert_eq!(cnt_trace(&mut m, 11), [0, 1, 2, 3, 0, 0, 0, 1, 1, 1, 2]);
}

// §12.3.1: the ARR preload "is transferred in the shadow register permanently or at each
// update event UEV, depending on the auto-reload preload enable bit (ARPE)".
#[test]
fn arr_without_preload_takes_effect_at_once() {
    let mut m = mcu();
    m.write(TIM1_ARR, 10);
    start_tim1(&mut m, 0);
    steps(&mut m, 6); // CNT = 5
    m.write(TIM1_ARR, 6);
    assert_eq!(cnt_trace(&mut m, 3), [6, 0, 1]);
}

#[test]
fn arr_with_preload_waits_for_the_update_event() {
    let mut m = mcu();
    m.write(TIM1_ARR, 10);
    m.write(TIM1_EGR, egr::UG.mask());
    start_tim1(&mut m, cr1::ARPE.mask());
    steps(&mut m, 6); // CNT = 5
    m.write(TIM1_ARR, 6);
    assert_eq!(cnt_trace(&mut m, 6), [6, 7, 8, 9, 10, 0]);
    assert_eq!(cnt_trace(&mut m, 8), [1, 2, 3, 4, 5, 6, 0, 1]);
}

// §12.3.3 "Repetition counter": preloads are transferred "every N+1 counter overflows
// ... where N is the value in the TIMx_RCR", and a UG "occurs immediately whatever the
// value of the repetition counter is and the repetition counter is reloaded with the
// content of the TIMx_RCR register". Brief (a): RCR = N-1 with ARPE/OC1PE, preloads
// written after a UG take effect only after N overflows.
#[test]
fn preloads_written_after_ug_apply_only_after_rcr_plus_one_overflows() {
    let mut m = mcu();
    m.write(TIM1_CR1, cr1::ARPE.mask());
    m.write(TIM1_RCR, 3); // N = 4
    tim1_ch1(&mut m, 9, 5, ocm::PWM1);
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::PWM1) | ccmr::ocpe(0).mask());
    m.write(TIM1_EGR, egr::UG.mask());
    m.write(TIM1_SR, 0);
    m.write(TIM1_ARR, 19);
    m.write(TIM1_CCR1, 15);
    start_tim1(&mut m, cr1::ARPE.mask());
    m.run_until(31); // third overflow (CNT = cycle - 1 mod 10): no update yet
    assert!(!uif1(&mut m));
    m.run_until(41);
    assert!(uif1(&mut m));
    m.run_until(70);
    let pa8: Vec<(u64, bool)> = m.edges().iter().map(|e| (e.cycle, e.high)).collect();
    let want = [(0, true), (6, false), (11, true), (16, false), (21, true), (26, false), (31, true)];
    assert_eq!(pa8[..7], want);
    // Fourth overflow at 41 is the repetition update: new ARR = 19, CCR1 = 15.
    assert_eq!(pa8[7..], [(36, false), (41, true), (56, false), (61, true)]);
}

// §12.3.3 (and efton.sk gotcha 142: RCR "is loaded into the actual repetition
// downcounter ... upon each Update Event"): REP_CNT is only loaded by an update event,
// so with RCR written at reset the very first overflow is an update.
#[test]
fn rcr_reaches_the_repetition_counter_only_at_an_update_event() {
    let mut m = mcu();
    m.write(TIM1_ARR, 9);
    m.write(TIM1_RCR, 3);
    start_tim1(&mut m, 0);
    m.run_until(11);
    assert!(uif1(&mut m), "REP_CNT was 0: the first overflow updates");
    m.write(TIM1_SR, 0);
    m.run_until(50);
    assert!(!uif1(&mut m));
    m.run_until(51);
    assert!(uif1(&mut m), "then every RCR+1 = 4 overflows");
}

#[test]
fn ug_reloads_the_repetition_counter_whatever_its_value() {
    let mut m = mcu();
    m.write(TIM1_ARR, 9);
    m.write(TIM1_RCR, 3);
    m.write(TIM1_EGR, egr::UG.mask());
    start_tim1(&mut m, 0);
    m.run_until(25); // two overflows: REP_CNT = 1
    m.write(TIM1_EGR, egr::UG.mask()); // CNT = 0, REP_CNT = 3
    m.write(TIM1_SR, 0);
    m.run_until(25 + 39);
    assert!(!uif1(&mut m));
    m.run_until(25 + 40);
    assert!(uif1(&mut m));
}

// §12.4.1 OPM: "Counter stops counting at the next update event (clearing the bit CEN)";
// with RCR that is the repetition update (§12.3.15, brief (b)).
#[test]
fn one_pulse_mode_stops_the_counter_at_the_repetition_update_event() {
    let mut m = mcu();
    m.write(TIM1_ARR, 4);
    m.write(TIM1_RCR, 2);
    m.write(TIM1_EGR, egr::UG.mask());
    start_tim1(&mut m, cr1::OPM.mask());
    m.run_until(15);
    assert!(cr1::CEN.on(m.read(TIM1_CR1)));
    assert_eq!(m.read(TIM1_CNT), 4);
    m.step(); // third overflow: update event
    assert!(!cr1::CEN.on(m.read(TIM1_CR1)));
    assert_eq!(cnt_trace(&mut m, 5), [0; 5]);
}

// §12.4.1 CEN: "CEN is cleared automatically in one-pulse mode, when an update event
// occurs" — any update event, a UG included (literal reading; no figure shows it).
#[test]
fn ug_in_one_pulse_mode_clears_cen() {
    let mut m = mcu();
    m.write(TIM1_ARR, 9);
    start_tim1(&mut m, cr1::OPM.mask());
    steps(&mut m, 3);
    m.write(TIM1_EGR, egr::UG.mask());
    assert!(!cr1::CEN.on(m.read(TIM1_CR1)));
    assert_eq!(cnt_trace(&mut m, 3), [0; 3]);
}

// §12.4.1 UDIS: "The Update event is not generated, shadow registers keep their value
// (ARR, PSC, CCRx). However the counter and the prescaler are reinitialized if the UG
// bit is set".
#[test]
fn udis_suppresses_update_events_but_ug_still_reinitialises_the_counter() {
    let mut m = mcu();
    m.write(TIM1_ARR, 9);
    m.write(TIM1_EGR, egr::UG.mask());
    m.write(TIM1_SR, 0);
    start_tim1(&mut m, cr1::ARPE.mask() | cr1::UDIS.mask());
    m.write(TIM1_ARR, 3);
    m.run_until(15);
    assert!(!uif1(&mut m));
    assert_eq!(m.read(TIM1_CNT), 4, "still wrapping at the old ARR shadow 9");
    m.write(TIM1_EGR, egr::UG.mask());
    assert_eq!(m.read(TIM1_CNT), 0);
    assert!(!uif1(&mut m));
    assert_eq!(cnt_trace(&mut m, 5), [1, 2, 3, 4, 5]);
}

// §12.4.1 URS: "1: Only counter overflow/underflow generates an update interrupt or DMA
// request if enabled" — UG still updates the registers.
#[test]
fn urs_makes_ug_update_registers_without_setting_uif() {
    let mut m = mcu();
    m.write(TIM1_CR1, cr1::URS.mask() | cr1::ARPE.mask());
    m.write(TIM1_ARR, 2);
    m.write(TIM1_EGR, egr::UG.mask());
    assert!(!uif1(&mut m));
    start_tim1(&mut m, cr1::URS.mask() | cr1::ARPE.mask());
    assert_eq!(cnt_trace(&mut m, 5), [0, 1, 2, 0, 1]);
    assert!(uif1(&mut m), "the overflow sets UIF");
}

// §12.4.12 ARR: "The counter is blocked while the auto-reload value is null."
#[test]
fn counter_is_blocked_while_arr_is_zero() {
    let mut m = mcu();
    start_tim1(&mut m, 0);
    assert_eq!(cnt_trace(&mut m, 5), [0; 5]);
    assert!(!uif1(&mut m));
}

// §12.4.5 SR is rc_w0: writing 0 clears a flag, writing 1 leaves it.
#[test]
fn status_flags_clear_on_zero_and_ignore_ones() {
    let mut m = mcu();
    m.write(TIM1_EGR, egr::UG.mask());
    m.write(TIM1_SR, !sr::ccif(0).mask());
    assert!(uif1(&mut m), "UIF written 1: unchanged");
    m.write(TIM1_SR, !sr::UIF.mask());
    assert!(!uif1(&mut m));
}
