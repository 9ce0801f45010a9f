//! TIM1 output compare, PWM and output enable: one test per manual statement.
mod common;
use common::*;

/// Step `n` cycles checking PA8 against `want(CNT)` after each.
fn check_pa8(m: &mut Mcu, n: usize, want: impl Fn(u32) -> bool) {
    for _ in 0..n {
        m.step();
        let cnt = m.read(TIM1_CNT);
        assert_eq!(m.pa8(), want(cnt), "cycle {} CNT {cnt}", m.cycle());
    }
}

// §12.3.10: PWM mode 1, "OCxREF is high as long as TIMx_CNT < TIMx_CCRx else it becomes
// low" — in the same cycle as the counter (Figure "Edge-aligned PWM waveforms").
#[test]
fn pwm1_ref_is_active_while_cnt_is_below_ccr() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 4, ocm::PWM1);
    start_tim1(&mut m, 0);
    check_pa8(&mut m, 35, |cnt| cnt < 4);
}

// §12.4.7 OC1M = 111, PWM mode 2: "channel 1 is inactive as long as TIMx_CNT<TIMx_CCR1
// else active" (brief (c)).
#[test]
fn pwm2_ref_is_inactive_while_cnt_is_below_ccr_else_active() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 4, ocm::PWM2);
    assert!(!m.pa8());
    start_tim1(&mut m, 0);
    check_pa8(&mut m, 35, |cnt| cnt >= 4);
}

// §12.3.10: "If the compare value in TIMx_CCRx is greater than the auto-reload value (in
// TIMx_ARR) then OCxREF is held at '1'" (PWM1), hence held at '0' in PWM2.
#[test]
fn ccr_above_arr_holds_ref_active_in_pwm1_and_inactive_in_pwm2() {
    for (mode, level) in [(ocm::PWM1, true), (ocm::PWM2, false)] {
        let mut m = mcu();
        tim1_ch1(&mut m, 9, 10, mode);
        start_tim1(&mut m, 0);
        check_pa8(&mut m, 35, |_| level);
    }
}

// §12.3.10: "If the compare value is 0 then OCxRef is held at '0'" (PWM1).
#[test]
fn ccr_zero_holds_ref_low_in_pwm1() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 0, ocm::PWM1);
    start_tim1(&mut m, 0);
    check_pa8(&mut m, 35, |_| false);
}

// §12.4.7 OC1M = 100 "Force inactive level - OC1REF is forced low" takes effect at the
// write; switching back to PWM re-evaluates REF from CNT/CCR at once (brief (d),
// §12.3.10 "TIMx_CNT and TIMx_CCRx are always compared"; default PwmModeSwitch).
#[test]
fn forced_inactive_drops_ref_at_once_and_pwm_mode_reevaluates_it() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 5, ocm::PWM1);
    start_tim1(&mut m, 0);
    steps(&mut m, 3); // CNT = 2, REF high
    assert!(m.pa8());
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::FORCE_INACTIVE));
    assert!(!m.pa8());
    assert_eq!(*m.edges().last().unwrap(), Edge { cycle: 3, pin: PinId::Pa8, high: false });
    check_pa8(&mut m, 10, |_| false);
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::PWM1)); // CNT = 2 again
    assert!(m.pa8());
    check_pa8(&mut m, 20, |cnt| cnt < 5);
}

// The stricter reading (OCxM note: "the OCREF level changes only when the result of the
// comparison changes or when the output compare mode switches from 'frozen' mode to
// 'PWM' mode"): leaving forced-inactive keeps REF low until the next change of the
// comparison; leaving frozen re-evaluates at once.
#[test]
fn only_from_frozen_reading_keeps_the_forced_level_until_the_comparison_changes() {
    let mut m = Mcu::new(Params { pwm_mode_switch: PwmModeSwitch::OnlyFromFrozen, ..Params::default() });
    tim1_ch1(&mut m, 9, 5, ocm::FORCE_INACTIVE);
    start_tim1(&mut m, 0);
    steps(&mut m, 3); // CNT = 2: comparison "active"
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::PWM1));
    assert!(!m.pa8());
    check_pa8(&mut m, 7, |_| false); // CNT 3..9, through the CNT = CCR1 match
    m.step(); // overflow: CNT = 0, the comparison turns active again
    assert!(m.pa8());
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::FROZEN));
    steps(&mut m, 7); // CNT = 7: frozen keeps REF high
    assert!(m.pa8());
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::PWM1));
    assert!(!m.pa8(), "frozen -> PWM re-evaluates");
}

// §12.4.7 OC1M = 101 "Force active level - OC1REF is forced high".
#[test]
fn forced_active_raises_ref_at_once() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 5, ocm::FORCE_ACTIVE);
    assert!(m.pa8());
}

// §12.4.7 / §12.3.9: 001 "OC1REF signal is forced high when the counter TIMx_CNT matches
// TIMx_CCR1", 010 forced low on match, 011 "OC1REF toggles when TIMx_CNT=TIMx_CCR1".
#[test]
fn match_modes_act_when_cnt_reaches_ccr() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 3, ocm::ACTIVE_ON_MATCH);
    start_tim1(&mut m, 0);
    check_pa8(&mut m, 3, |_| false);
    check_pa8(&mut m, 20, |_| true);

    let mut m = mcu();
    tim1_ch1(&mut m, 9, 3, ocm::FORCE_ACTIVE);
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::INACTIVE_ON_MATCH));
    start_tim1(&mut m, 0);
    check_pa8(&mut m, 3, |_| true);
    check_pa8(&mut m, 20, |_| false);

    let mut m = mcu();
    tim1_ch1(&mut m, 9, 3, ocm::TOGGLE);
    start_tim1(&mut m, 0);
    m.run_until(50);
    let cycles: Vec<u64> = m.edges().iter().map(|e| e.cycle).collect();
    assert_eq!(cycles, [4, 14, 24, 34, 44]);
}

// §12.4.7 OC1M = 000 "Frozen - The comparison ... has no effect on the outputs", while
// §12.4.5 CC1IF is still "set by hardware when the counter matches the compare value".
#[test]
fn frozen_keeps_ref_but_the_match_still_sets_ccxif() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 3, ocm::FORCE_ACTIVE);
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::FROZEN));
    start_tim1(&mut m, 0);
    steps(&mut m, 3);
    assert!(!sr::ccif(0).on(m.read(TIM1_SR)));
    check_pa8(&mut m, 25, |_| true);
    assert!(sr::ccif(0).on(m.read(TIM1_SR)));
}

// §12.4.9 CCER and its table "Output control bits for complementary OCx and OCxN
// channels with break feature" (CCxNE = 0 rows): OCx = OCxREF xor CCxP with CCxE = 1
// and MOE = 1; otherwise the output is not driven (reads low here). Brief (i).
#[test]
fn oc_output_is_ref_xor_ccxp_only_with_ccxe_and_moe() {
    let mut m = mcu();
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::FORCE_ACTIVE) | ccmr::ocm(1).val(ocm::FORCE_INACTIVE));
    let both = ccer::cce(0).mask() | ccer::cce(1).mask();
    m.write(TIM1_CCER, both);
    assert_eq!((m.pa8(), m.pa9()), (false, false), "MOE = 0");
    m.write(TIM1_BDTR, bdtr::MOE.mask());
    assert_eq!((m.pa8(), m.pa9()), (true, false));
    m.write(TIM1_CCER, both | ccer::ccp(0).mask() | ccer::ccp(1).mask());
    assert_eq!((m.pa8(), m.pa9()), (false, true));
    m.write(TIM1_CCER, ccer::ccp(0).mask() | ccer::ccp(1).mask());
    assert_eq!((m.pa8(), m.pa9()), (false, false), "CCxE = 0");
}

// §12.4.7 OC1PE: "0: TIMx_CCR1 can be written at anytime, the new value is taken in
// account immediately. 1: ... the preload value is loaded in the active register at each
// update event."
#[test]
fn ccr_preload_waits_for_the_update_event_and_no_preload_acts_at_once() {
    let mut m = mcu();
    tim1_ch1(&mut m, 9, 5, ocm::PWM1);
    m.write(TIM1_CCMR1, ccmr::ocm(0).val(ocm::PWM1) | ccmr::ocpe(0).mask());
    m.write(TIM1_EGR, egr::UG.mask());
    start_tim1(&mut m, 0);
    steps(&mut m, 4); // CNT = 3
    m.write(TIM1_CCR1, 2);
    assert!(m.pa8());
    check_pa8(&mut m, 7, |cnt| cnt < 5); // rest of this period: old compare value
    check_pa8(&mut m, 20, |cnt| cnt < 2);

    let mut m = mcu();
    tim1_ch1(&mut m, 9, 5, ocm::PWM1);
    start_tim1(&mut m, 0);
    steps(&mut m, 4);
    m.write(TIM1_CCR1, 2);
    assert!(!m.pa8(), "CNT 3 >= new CCR1 2");
}
