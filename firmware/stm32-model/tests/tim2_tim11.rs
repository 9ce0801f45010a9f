//! TIM2 clocked by TIM1's TRGO through ITR0, TIM1's master modes, and TIM11's tick.
mod common;
use common::*;

/// TIM2 in external clock mode 1 on ITR0, ARR at its maximum, counting.
fn tim2_on_itr0(m: &mut Mcu) {
    m.write(TIM2_SMCR, smcr::SMS.val(smcr::SMS_EXT_CLOCK_1) | smcr::TS.val(smcr::TS_ITR0));
    m.write(TIM2_ARR, u32::MAX);
    m.write(TIM2_CR1, cr1::CEN.mask());
}

fn tim1_mms(m: &mut Mcu, mms: u32) {
    m.write(TIM1_CR2, cr2::MMS.val(mms));
}

/// TIM2 CNT at every cycle in `cycles`.
fn tim2_trace(m: &mut Mcu, cycles: std::ops::RangeInclusive<u64>) -> Vec<u32> {
    cycles
        .map(|c| {
            m.run_until(c);
            m.read(TIM2_CNT)
        })
        .collect()
}

// §13.4.3 SMS = 111 "External Clock Mode 1 - Rising edges of the selected trigger (TRGI)
// clock the counter", TS = 000 = ITR0 = TIM1 TRGO (§13.3.15 example, table "TIMx
// internal trigger connection"); §12.4.2 MMS = 100: "OC1REF signal is used as trigger
// output (TRGO)"; §13.3.3: counted after the resynchronisation delay. Brief (h).
#[test]
fn ext_clock_mode_1_counts_each_oc1ref_rising_edge_once_after_the_resync_delay() {
    let mut m = mcu(); // resync 2
    tim2_on_itr0(&mut m);
    tim1_mms(&mut m, cr2::MMS_OC1REF);
    tim1_ch1(&mut m, 9, 4, ocm::PWM2); // REF rises when CNT becomes 4: cycles 5, 15, 25
    start_tim1(&mut m, 0);
    let got = tim2_trace(&mut m, 0..=30);
    let want: Vec<u32> = (0..=30u64).map(|c| [7, 17, 27].iter().filter(|&&t| t <= c).count() as u32).collect();
    assert_eq!(got, want);
}

#[test]
fn the_resync_delay_is_a_parameter() {
    let mut m = Mcu::new(Params { tim2_resync_cycles: 5, ..Params::default() });
    tim2_on_itr0(&mut m);
    tim1_mms(&mut m, cr2::MMS_OC1REF);
    tim1_ch1(&mut m, 9, 4, ocm::PWM2);
    start_tim1(&mut m, 0);
    assert_eq!(tim2_trace(&mut m, 9..=11), [0, 1, 1]);
}

#[test]
fn a_ref_that_stays_high_is_never_counted() {
    let mut m = mcu();
    tim1_mms(&mut m, cr2::MMS_OC1REF);
    tim1_ch1(&mut m, 9, 10, ocm::PWM1); // CCR1 > ARR: REF held at 1
    start_tim1(&mut m, 0);
    m.run_until(5);
    tim2_on_itr0(&mut m);
    m.run_until(10_000);
    assert_eq!(m.read(TIM2_CNT), 0);
}

// §12.4.2 MMS = 010 "the update event is selected as trigger output (TRGO)": TIM2 counts
// TIM1's update events (§13.3.15 "Using one timer as prescaler for another timer").
#[test]
fn mms_update_makes_tim2_count_tim1_update_events() {
    let mut m = mcu();
    tim2_on_itr0(&mut m);
    tim1_mms(&mut m, cr2::MMS_UPDATE);
    m.write(TIM1_ARR, 9);
    m.write(TIM1_RCR, 1);
    start_tim1(&mut m, 0); // REP_CNT 0: updates at overflows 1, 3, 5...: cycles 11, 31, 51
    assert_eq!(tim2_trace(&mut m, 12..=14), [0, 1, 1]);
    m.run_until(100);
    assert_eq!(m.read(TIM2_CNT), 5);
}

// §12.4.2 MMS = 000 "the UG bit from the TIMx_EGR register is used as trigger output".
#[test]
fn mms_reset_pulses_trgo_on_ug() {
    let mut m = mcu();
    tim2_on_itr0(&mut m);
    for k in 1..=3 {
        m.write(TIM1_EGR, egr::UG.mask());
        m.run_until(10 * k);
        assert_eq!(m.read(TIM2_CNT), k as u32);
    }
}

// §12.4.2 MMS = 001 "the Counter Enable signal CNT_EN is used as trigger output".
#[test]
fn mms_enable_outputs_cnt_en() {
    let mut m = mcu();
    tim2_on_itr0(&mut m);
    tim1_mms(&mut m, cr2::MMS_ENABLE);
    m.write(TIM1_ARR, 9);
    start_tim1(&mut m, 0);
    m.run_until(50);
    m.write(TIM1_CR1, 0);
    start_tim1(&mut m, 0); // CEN low between two clock edges: CNT_EN never falls
    m.run_until(60);
    assert_eq!(m.read(TIM2_CNT), 1);
    m.write(TIM1_CR1, 0);
    m.run_until(70);
    start_tim1(&mut m, 0);
    m.run_until(100);
    assert_eq!(m.read(TIM2_CNT), 2);
}

// §12.4.2 MMS = 011 "Compare Pulse - The trigger output send a positive pulse when the
// CC1IF flag is to be set (even if it was already high), as soon as ... a compare match".
#[test]
fn mms_compare_pulse_pulses_on_every_cc1_match() {
    let mut m = mcu();
    tim2_on_itr0(&mut m);
    tim1_mms(&mut m, cr2::MMS_COMPARE_PULSE);
    tim1_ch1(&mut m, 9, 3, ocm::FROZEN);
    start_tim1(&mut m, 0); // matches at cycles 4, 14, 24
    m.run_until(26);
    assert_eq!(m.read(TIM2_CNT), 3);
}

// §13.4.3: SMS = 000 "the prescaler is clocked directly by the internal clock"; the
// 32-bit counter wraps at ARR (§13.3.2) and its prescaler divides the external edges too.
#[test]
fn tim2_counts_ck_int_without_slave_mode_and_wraps_at_arr() {
    let mut m = mcu();
    m.write(TIM2_ARR, 4);
    m.write(TIM2_CR1, cr1::CEN.mask());
    assert_eq!(tim2_trace(&mut m, 1..=8), [0, 1, 2, 3, 4, 0, 1, 2]);
    assert!(sr::UIF.on(m.read(TIM2_SR)));
}

#[test]
fn tim2_prescaler_divides_trigger_edges() {
    let mut m = mcu();
    m.write(TIM2_PSC, 1);
    m.write(TIM2_EGR, egr::UG.mask());
    tim2_on_itr0(&mut m);
    tim1_mms(&mut m, cr2::MMS_UPDATE);
    m.write(TIM1_ARR, 9);
    start_tim1(&mut m, 0);
    m.run_until(100); // 9 updates counted
    assert_eq!(m.read(TIM2_CNT), 4);
}

// §14.3.1-2: TIM11 counts CK_INT/(PSC+1) from 0 to ARR and generates an update at each
// overflow, i.e. one every (PSC+1)(ARR+1) cycles. Brief (j).
#[test]
fn tim11_updates_every_psc_plus_one_times_arr_plus_one_cycles() {
    let mut m = mcu();
    m.write(TIM11_PSC, 2);
    m.write(TIM11_ARR, 4);
    m.write(TIM11_EGR, egr::UG.mask()); // loads PSC; counts as an update event
    m.write(TIM11_CR1, cr1::CEN.mask());
    assert_eq!(m.tim11_updates(), 1);
    m.run_until(15);
    assert_eq!(m.tim11_updates(), 1);
    m.run_until(16);
    assert_eq!(m.tim11_updates(), 2);
    m.run_until(16 + 15 * 1000 - 1);
    assert_eq!(m.tim11_updates(), 1001);
    m.step();
    assert_eq!(m.tim11_updates(), 1002);
    assert_eq!(m.tim11_uif_sets(), 1002);
    assert!(sr::UIF.on(m.read(TIM11_SR)));
}

// §14.5.1 URS = 1: "Only counter overflow/underflow generates an update interrupt": the
// UG still is an update event, but sets no UIF.
#[test]
fn tim11_ug_with_urs_updates_without_setting_uif() {
    let mut m = mcu();
    m.write(TIM11_CR1, cr1::URS.mask());
    m.write(TIM11_EGR, egr::UG.mask());
    assert_eq!((m.tim11_updates(), m.tim11_uif_sets()), (1, 0));
    assert!(!sr::UIF.on(m.read(TIM11_SR)));
}
