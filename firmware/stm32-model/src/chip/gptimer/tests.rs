use super::*;

const MHZ96: u64 = 96_000_000;

fn running(psc: u32, arr: u32) -> GpTimer {
    let mut t = GpTimer::new(16, 4);
    t.write(PSC, psc, u32::MAX);
    t.write(ARR, arr, u32::MAX);
    t.write(EGR, 1, u32::MAX); // UG loads PSC (§13.3.1: "taken into account at the next update event")
    t.write(SR, 0, u32::MAX);
    t.write(CR1, CEN, u32::MAX);
    t
}

#[test]
fn the_counter_overflows_every_psc_plus_1_times_arr_plus_1_clocks() {
    let mut t = running(1, 99);
    t.advance(199, MHZ96, MHZ96);
    assert_eq!((t.read(CNT), t.read(SR) & 1), (99, 0));
    t.advance(200, MHZ96, MHZ96);
    assert_eq!((t.read(CNT), t.read(SR) & 1, t.updates), (0, 1, 2));
}

#[test]
fn a_timer_on_a_slower_clock_counts_by_the_ratio() {
    let mut t = running(0, 0xFFFF);
    t.advance(1000, MHZ96, MHZ96 / 2);
    assert_eq!(t.read(CNT), 500);
}

#[test]
fn next_event_names_the_cycle_the_flag_is_set_in() {
    let mut t = running(2, 9);
    t.write(DIER, 1 | 1 << 2, u32::MAX); // UIE, CC2IE
    t.write(CCR1 + 4, 4, u32::MAX);
    let at = t.next_event(MHZ96, MHZ96).unwrap();
    assert_eq!(at, 12, "CNT 0 -> 4 takes 4 counts of 3 clocks");
    t.advance(at - 1, MHZ96, MHZ96);
    assert!(!t.irq(0x1F));
    t.advance(at, MHZ96, MHZ96);
    assert!(t.irq(1 << 2));
}

#[test]
fn flags_are_rc_w0_and_ug_with_urs_sets_no_uif() {
    let mut t = running(0, 9);
    t.write(EGR, 1 << 1, u32::MAX);
    assert_eq!(t.read(SR), 2, "CC1G sets CC1IF");
    t.write(SR, !2, u32::MAX);
    assert_eq!(t.read(SR), 0);
    t.write(CR1, CEN | URS, u32::MAX);
    t.write(EGR, 1, u32::MAX);
    assert_eq!(t.read(SR), 0, "§13.4.1 URS: UG sets no UIF");
}

#[test]
fn encoder_counts_wrap_through_arr_both_ways() {
    let mut t = running(0, 9);
    t.write(SMCR, 3, u32::MAX);
    assert!(t.encoder_mode());
    t.count_by(-1);
    assert_eq!((t.read(CNT), t.read(SR) & 1), (9, 1));
    t.count_by(3);
    assert_eq!(t.read(CNT), 2);
}

#[test]
fn pwm_mode_1_is_high_below_ccr_and_the_pin_off_without_ccxe() {
    let mut t = running(0, 99);
    t.write(CCMR1, 6 << 4, u32::MAX);
    t.write(CCR1, 30, u32::MAX);
    assert_eq!(t.oc_out(0), None);
    t.write(CCER, 1, u32::MAX);
    t.advance(10, MHZ96, MHZ96);
    assert_eq!(t.oc_out(0), Some(true));
    t.advance(40, MHZ96, MHZ96);
    assert_eq!(t.oc_out(0), Some(false));
}

#[test]
fn quadrature_counts_up_one_way_and_down_the_other_with_dir() {
    let mut t = running(0, 0xFFFF);
    t.write(SMCR, 3, u32::MAX); // encoder mode 3
    let seq = [[true, false], [true, true], [false, true], [false, false]];
    for ab in seq {
        t.inputs([ab[0], ab[1], false]);
    }
    assert_eq!(t.read(CNT), 4);
    assert_eq!(t.read(CR1) & 0x10, 0, "counting up: DIR = 0");
    for ab in seq.iter().rev().skip(1) {
        t.inputs([ab[0], ab[1], false]);
    }
    t.inputs([false, false, false]);
    assert_eq!(t.read(CNT), 0, "table 53 both ways: {:?}", t.read(CNT));
    assert_eq!(t.read(CR1) & 0x10, 0x10, "counting down: DIR = 1");
}

#[test]
fn the_index_captures_cnt_and_a_read_of_ccr3_clears_the_flag() {
    let mut t = running(0, 0xFFFF);
    t.write(SMCR, 3, u32::MAX);
    t.write(CCMR2, 1, u32::MAX); // CC3S = 01: IC3 on TI3
    t.write(CCER, 1 << 8, u32::MAX);
    t.inputs([true, false, false]);
    t.inputs([true, false, true]);
    assert_eq!(t.read(SR) & 1 << 3, 1 << 3);
    t.inputs([true, false, false]);
    t.inputs([true, false, true]);
    assert_eq!(t.read(SR) & 1 << 11, 1 << 11, "CC3OF: captured twice unread");
    assert_eq!(t.read(CCR1 + 8), 1);
    assert_eq!(t.read(SR) & 1 << 3, 0);
}

#[test]
fn counting_past_zero_sets_no_flag_on_an_input_channel() {
    let mut t = running(0, 0xFFFF);
    t.write(SMCR, 3, u32::MAX);
    t.write(CCMR2, 1, u32::MAX); // channel 3 an input: §13.4.5 "set by hardware on a capture"
    t.write(CCER, 1 << 8, u32::MAX);
    t.write(SR, 0, u32::MAX);
    t.inputs([true, false, false]);
    t.inputs([false, false, false]);
    assert_eq!(t.read(SR) & 1 << 3, 0, "CNT back to CCR3's 0: no capture, no flag");
}

#[test]
fn a_prescaler_loaded_by_an_update_counts_the_rest_of_the_slice() {
    let mut t = GpTimer::new(16, 1);
    t.write(ARR, 9, u32::MAX);
    t.write(PSC, 9, u32::MAX); // preloaded: /1 until the first update (§13.3.1)
    t.write(CR1, CEN, u32::MAX);
    t.advance(10 + 100, MHZ96, MHZ96); // 10 clocks at /1, then 100 at /10
    assert_eq!((t.read(CNT), t.updates), (0, 2));
    t.advance(10 + 100 + 90, MHZ96, MHZ96);
    assert_eq!(t.read(CNT), 9);
}

#[test]
fn ug_with_udis_restarts_the_counter_without_an_update() {
    let mut t = running(0, 99);
    t.advance(50, MHZ96, MHZ96);
    t.write(CR1, CEN | UDIS, u32::MAX);
    let before = t.updates;
    t.write(EGR, 1, u32::MAX);
    assert_eq!((t.read(CNT), t.read(SR) & 1, t.updates), (0, 0, before), "§13.3.2");
}

#[test]
fn ug_counting_down_loads_arr() {
    let mut t = running(0, 99);
    t.write(SMCR, 3, u32::MAX);
    t.inputs([false, true, false]); // B leads: a down count, DIR = 1
    t.write(EGR, 1, u32::MAX);
    assert_eq!(t.read(CNT), 99, "§13.4.6: takes the auto-reload value if DIR = 1");
}

#[test]
#[should_panic(expected = "not modelled")]
fn tim10_has_no_one_pulse_mode() {
    // TIM10_CR1 (§14.5.1) has no OPM: bit 3 is reserved there
    GpTimer::new(16, 1).write(CR1, 1 << 3, u32::MAX);
}

#[test]
fn tim10_takes_its_own_bits() {
    let mut t = GpTimer::new(16, 1);
    t.write(CR1, 0x81, u32::MAX); // ARPE | CEN
    t.write(CCMR1, 0x68, u32::MAX); // PWM mode 1, OC1PE
    t.write(CCER, 1, u32::MAX);
    assert_eq!((t.get(CR1), t.get(CCMR1), t.get(CCER)), (0x81, 0x68, 1));
}
