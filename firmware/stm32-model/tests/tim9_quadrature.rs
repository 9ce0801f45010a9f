//! TIM9 (RM0383 chapter 14): its time base and its two output-compare channels, one test
//! per manual statement; then both channels in toggle mode decoded by the
//! encoder-interface model (`encoder`), with register values chosen here from the
//! manual, not taken from the firmware.
mod common;
use common::*;
use polyturn_stm32_model::encoder::{Counting, Encoder};

/// Both channels in `mode`, CCRs and ARR written, outputs on.
fn tim9(m: &mut Mcu, arr: u32, ccr: [u32; 2], ccmr1: u32) {
    m.write(TIM9_ARR, arr);
    m.write(TIM9_CCR1, ccr[0]);
    m.write(TIM9_CCR2, ccr[1]);
    m.write(TIM9_CCMR1, ccmr1);
    m.write(TIM9_CCER, ccer::cce(0).mask() | ccer::cce(1).mask());
}

fn both(mode: u32) -> u32 {
    ccmr::ocm(0).val(mode) | ccmr::ocm(1).val(mode)
}

fn rises(m: &Mcu, pin: PinId) -> Vec<u64> {
    m.edges().iter().filter(|e| e.pin == pin && e.high).map(|e| e.cycle).collect()
}

// §14.3.1-2: the counter counts CK_INT/(PSC+1) from 0 to ARR, then an update event: one
// every (PSC+1)(ARR+1) cycles once CNT_EN follows CEN, one cycle after it (§14.3.1).
#[test]
fn tim9_updates_every_psc_plus_one_times_arr_plus_one_cycles() {
    let mut m = mcu();
    m.write(TIM9_PSC, 3);
    m.write(TIM9_ARR, 9);
    m.write(TIM9_CR1, cr1::URS.mask());
    m.write(TIM9_EGR, egr::UG.mask()); // loads PSC; no UIF with URS = 1 (§14.4.1)
    assert_eq!((m.tim9_updates(), m.tim9_uif_sets()), (1, 0));
    m.write(TIM9_CR1, cr1::URS.mask() | cr1::CEN.mask());
    assert!(m.run_to_tim9_update(10_000));
    assert_eq!(m.cycle(), 1 + 40);
    assert!(m.run_to_tim9_update(10_000));
    assert_eq!(m.cycle(), 1 + 80);
    assert!(sr::UIF.on(m.read(TIM9_SR)));
    m.write(TIM9_SR, !sr::UIF.mask()); // rc_w0 (§14.4.4)
    assert!(!sr::UIF.on(m.read(TIM9_SR)));
}

/// The cycle UIF was last set, for a handler timed from its update event:
/// an overflow's (§14.3.2), and a UG's with URS = 0 (§14.4.1: "any of the
/// following events generate an update interrupt … setting the UG bit"),
/// not a UG's with URS = 1.
#[test]
fn the_cycle_tim9_last_set_uif_is_kept_for_an_overflow_and_a_ug() {
    let mut m = mcu();
    m.write(TIM9_ARR, 9);
    m.write(TIM9_CR1, cr1::URS.mask());
    m.write(TIM9_EGR, egr::UG.mask());
    assert_eq!(m.tim9_uif_at(), 0, "no UIF from a UG with URS = 1");
    m.write(TIM9_CR1, cr1::URS.mask() | cr1::CEN.mask());
    assert!(m.run_to_tim9_update(10_000));
    assert_eq!(m.tim9_uif_at(), m.cycle());
    m.run_until(m.cycle() + 3);
    m.write(TIM9_CR1, cr1::CEN.mask());
    m.write(TIM9_EGR, egr::UG.mask());
    assert_eq!(m.tim9_uif_at(), m.cycle(), "a UG with URS = 0 sets UIF now");
}

// §14.4.6 OC1M = 011 "Toggle - OC1REF toggles when TIMx_CNT = TIMx_CCR1", CC1IF set at
// the match (§14.4.4); OC1 = OC1REF with CC1E = 1, CC1P = 0 (§14.4.7).
#[test]
fn toggle_mode_toggles_at_every_match_so_the_pin_has_twice_the_update_period() {
    let mut m = mcu();
    tim9(&mut m, 9, [3, 7], both(ocm::TOGGLE));
    m.write(TIM9_CR1, cr1::CEN.mask());
    m.run_until(100);
    let pa2: Vec<(u64, bool)> = m.edges().iter().filter(|e| e.pin == PinId::Pa2).map(|e| (e.cycle, e.high)).collect();
    assert_eq!(pa2[..4], [(4, true), (14, false), (24, true), (34, false)]);
    assert_eq!(rises(&m, PinId::Pa3)[..2], [8, 28]);
    assert_eq!(m.read(TIM9_SR) & 0b110, 0b110);
}

// §14.4.6 OC1PE = 1: "TIMx_CCR1 preload value is loaded in the active register at each
// update event"; OC1PE = 0: "the new value is taken in account immediately".
#[test]
fn ccr_preload_defers_a_new_compare_value_to_the_update_event() {
    for (preload, want) in [(true, vec![4, 16, 26]), (false, vec![4, 6, 16, 26])] {
        let mut m = mcu();
        let pe = ccmr::ocpe(0).val(preload as u32);
        tim9(&mut m, 9, [3, 20], both(ocm::TOGGLE) | pe);
        m.write(TIM9_CR1, cr1::CEN.mask());
        m.run_until(5);
        m.write(TIM9_CCR1, 5); // CNT = 4: now, or from the update at cycle 11
        m.run_until(30);
        let edges: Vec<u64> = m.edges().iter().filter(|e| e.pin == PinId::Pa2).map(|e| e.cycle).collect();
        assert_eq!(edges, want, "OC1PE = {preload}");
    }
}

// §14.3.7 / §14.4.6 OCxM = 100 / 101: OCxREF forced low / high at the write; a switch to
// toggle keeps the level until the next match.
#[test]
fn forced_levels_act_at_once_and_toggle_starts_from_them() {
    let mut m = mcu();
    tim9(&mut m, 9, [3, 3], ccmr::ocm(0).val(ocm::FORCE_ACTIVE) | ccmr::ocm(1).val(ocm::FORCE_INACTIVE));
    assert!(m.pa2() && !m.pa3());
    m.write(TIM9_CCMR1, both(ocm::TOGGLE));
    assert!(m.pa2() && !m.pa3());
    m.write(TIM9_CR1, cr1::CEN.mask());
    m.run_until(5); // match at CNT = 3 (cycle 4)
    assert!(!m.pa2() && m.pa3());
}

// §14.4.7: CC1P = 1 "OC1 active low"; CC2E = 0: "OC2 is not active" (the pin reads low).
#[test]
fn polarity_inverts_and_a_disabled_output_reads_low() {
    let mut m = mcu();
    m.write(TIM9_CCMR1, both(ocm::FORCE_ACTIVE));
    m.write(TIM9_CCER, ccer::cce(0).mask() | ccer::ccp(0).mask());
    assert!(!m.pa2() && !m.pa3());
    m.write(TIM9_CCMR1, both(ocm::FORCE_INACTIVE));
    assert!(m.pa2() && !m.pa3());
}

// §14.4.1 OPM = 1: "Counter stops counting at the next update event (clearing the bit
// CEN)": no compare match after it.
#[test]
fn one_pulse_mode_stops_the_counter_at_the_next_update_event() {
    let mut m = mcu();
    tim9(&mut m, 9, [1, 5], both(ocm::TOGGLE));
    m.write(TIM9_CNT, 7);
    m.write(TIM9_CR1, cr1::CEN.mask() | cr1::OPM.mask());
    m.run_until(1_000);
    assert_eq!(m.tim9_updates(), 1);
    assert_eq!(m.read(TIM9_CR1) & cr1::CEN.mask(), 0);
    assert_eq!(m.read(TIM9_CNT), 0);
    assert!(m.edges().is_empty(), "{:?}", m.edges());
}

#[test]
#[should_panic(expected = "PWM")]
fn pwm_mode_on_tim9_is_refused() {
    mcu().write(TIM9_CCMR1, ccmr::ocm(1).val(ocm::PWM1));
}

#[test]
#[should_panic(expected = "0x40014008")]
fn a_slave_mode_on_tim9_is_refused_with_its_address() {
    mcu().write(TIM9_SMCR, smcr::SMS.val(4));
}

#[test]
#[should_panic(expected = "CCxNP")]
fn ccxnp_on_an_output_is_refused() {
    mcu().write(TIM9_CCER, ccer::ccnp(0).mask());
}

/// TIM9 toggling A (CH1) at CNT = `c1` and B (CH2) at `c2` for `periods` update periods
/// of ARR = `arr`, from both low; the signed count an encoder in mode 3 makes of it.
fn decoded(c1: u32, c2: u32, arr: u32, periods: u64) -> (i64, u64) {
    let mut m = mcu();
    tim9(&mut m, arr, [c1, c2], both(ocm::TOGGLE));
    m.write(TIM9_CR1, cr1::CEN.mask());
    m.run_until(1 + periods * (arr as u64 + 1));
    let mut enc = Encoder::new(Counting::Both, 0xFFFF, [false; 3]);
    let (mut a, mut b, mut min_gap, mut last) = (false, false, u64::MAX, None::<u64>);
    for e in m.edges() {
        match e.pin {
            PinId::Pa2 => a = e.high,
            _ => b = e.high,
        }
        enc.input(a, b);
        min_gap = min_gap.min(last.map_or(u64::MAX, |l| e.cycle - l));
        last = Some(e.cycle);
    }
    (enc.position(), min_gap)
}

// One toggle of A and one of B per update period, A first (Table 53: TI1 rising with TI2
// low counts up, TI2 rising with TI1 high counts up...): two counts up per period, edges
// half a period apart. With the compare values swapped B leads: two counts down.
#[test]
fn two_toggle_channels_make_two_quadrature_counts_per_update_period() {
    assert_eq!(decoded(1, 51, 99, 40), (80, 50));
    assert_eq!(decoded(51, 1, 99, 40), (-80, 50));
}

/// One random TIM9 register write the model accepts (xorshift64*, no dependency).
fn random_write(r: &mut u64) -> (u32, u32) {
    let mut next = |n: u64| {
        *r ^= *r >> 12;
        *r ^= *r << 25;
        *r ^= *r >> 27;
        (r.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) as u32 % n as u32
    };
    match next(10) {
        0 => {
            let v = cr1::CEN.val(next(4).min(1))
                | cr1::URS.val(next(2))
                | cr1::ARPE.val(next(2))
                | cr1::OPM.val((next(6) == 0) as u32)
                | cr1::UDIS.val((next(8) == 0) as u32);
            (TIM9_CR1, v)
        }
        1 => {
            let ch = |c: u32, m: u32, pe: u32| ccmr::ocm(c).val(m) | ccmr::ocpe(c).val(pe);
            (TIM9_CCMR1, ch(0, next(6), next(2)) | ch(1, next(6), next(2)))
        }
        2 => (TIM9_CCER, (0..2).fold(0, |v, c| v | ccer::cce(c).val(next(4).min(1)) | ccer::ccp(c).val(next(2)))),
        3 => (TIM9_CNT, next(64)),
        4 => (TIM9_PSC, next(4)),
        5 => (TIM9_ARR, next(60)),
        6 => (TIM9_CCR1, next(70)),
        7 => (TIM9_CCR2, next(70)),
        8 => (TIM9_EGR, egr::UG.mask()),
        _ => (TIM9_SR, next(8)),
    }
}

// `run_until`'s fast path skips TIM9's quiet stretches: it must agree with stepping
// cycle by cycle (registers, counters, pins and edges).
#[test]
fn run_until_agrees_with_stepping_on_tim9() {
    let mut r = 0x9E37_79B9_7F4A_7C15u64;
    for _ in 0..300 {
        let (mut stepped, mut fast) = (mcu(), mcu());
        for _ in 0..10 {
            let (addr, v) = random_write(&mut r);
            stepped.write(addr, v);
            fast.write(addr, v);
            let until = stepped.cycle() + (r % 400);
            while stepped.cycle() < until {
                stepped.step();
            }
            fast.run_until(until);
            assert_eq!(stepped, fast, "after {addr:#x} = {v:#x}");
        }
    }
}
