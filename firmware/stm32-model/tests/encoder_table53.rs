//! The encoder-interface model against RM0383 §13.3.12: a test per row of Table 53
//! "Counting direction versus encoder signals" (the expected counts are restated here
//! from the manual, not read from the model's table), the counter's range, DIR, and
//! channel 3's capture of the count at the index (§13.3.5).
use polyturn_stm32_model::encoder::{Count, Counting, Encoder};
use Count::{Down, None as No, Up};

/// The counts of one row: an edge on each column's input (TI1 rising, TI1 falling, TI2
/// rising, TI2 falling), each from a fresh encoder with the opposite input at `high`.
fn row(counting: Counting, high: bool) -> [Count; 4] {
    // (TI1, TI2) before and after each column's edge
    let cols = [((false, high), (true, high)), ((true, high), (false, high))];
    let cols2 = [((high, false), (high, true)), ((high, true), (high, false))];
    let mut out = [No; 4];
    for (i, (from, to)) in cols.into_iter().chain(cols2).enumerate() {
        let mut e = Encoder::new(counting, 99, [from.0, from.1, false]);
        out[i] = e.input(to.0, to.1);
        let want_cnt = match out[i] {
            Up => 1,
            Down => 99,
            No => 0,
        };
        assert_eq!(e.cnt(), want_cnt, "column {i}");
    }
    out
}

#[test]
fn table_53_counting_on_ti1_only_opposite_high() {
    assert_eq!(row(Counting::Ti1Only, true), [Down, Up, No, No]);
}

#[test]
fn table_53_counting_on_ti1_only_opposite_low() {
    assert_eq!(row(Counting::Ti1Only, false), [Up, Down, No, No]);
}

#[test]
fn table_53_counting_on_ti2_only_opposite_high() {
    assert_eq!(row(Counting::Ti2Only, true), [No, No, Up, Down]);
}

#[test]
fn table_53_counting_on_ti2_only_opposite_low() {
    assert_eq!(row(Counting::Ti2Only, false), [No, No, Down, Up]);
}

// SMS = 011 (§13.4.3 "Encoder mode 3"), TIM3's mode for the lathe encoder.
#[test]
fn table_53_counting_on_ti1_and_ti2_opposite_high() {
    assert_eq!(row(Counting::Both, true), [Down, Up, Up, Down]);
}

#[test]
fn table_53_counting_on_ti1_and_ti2_opposite_low() {
    assert_eq!(row(Counting::Both, false), [Up, Down, Down, Up]);
}

/// Feeds (TI1, TI2) levels in turn.
fn walk(e: &mut Encoder, levels: &[(u8, u8)]) {
    for &(a, b) in levels {
        e.input(a == 1, b == 1);
    }
}

// §13.3.12 Figure "Example of counter operation in encoder interface mode": TI1 leading
// TI2 counts up at every edge, TI2 leading counts down, and jitter on one input (an edge
// and its return) leaves the count unchanged.
#[test]
fn a_full_cycle_forward_is_four_up_backward_four_down_and_jitter_cancels() {
    let mut e = Encoder::new(Counting::Both, 0xFFFF, [false; 3]);
    walk(&mut e, &[(1, 0), (1, 1), (0, 1), (0, 0)]);
    assert_eq!((e.position(), e.cnt(), e.dir_down()), (4, 4, false));
    walk(&mut e, &[(1, 0), (0, 0), (1, 0), (0, 0)]);
    assert_eq!(e.position(), 4);
    walk(&mut e, &[(0, 1), (1, 1), (1, 0), (0, 0)]);
    assert_eq!((e.position(), e.cnt(), e.dir_down()), (0, 0, true));
}

// "The counter just counts continuously between 0 and the auto-reload value ... (0 to
// ARR or ARR down to 0 depending on the direction)".
#[test]
fn the_counter_wraps_between_zero_and_arr() {
    let mut e = Encoder::new(Counting::Both, 2, [false; 3]);
    walk(&mut e, &[(1, 0), (1, 1), (0, 1)]);
    assert_eq!((e.cnt(), e.position()), (0, 3));
    walk(&mut e, &[(1, 1)]);
    assert_eq!((e.cnt(), e.position()), (2, 2));
}

// "The DIR bit is calculated at each transition on any input (TI1 or TI2), whatever the
// counter is counting on TI1 only, TI2 only or both TI1 and TI2."
#[test]
fn dir_follows_a_transition_the_counter_does_not_count() {
    let mut e = Encoder::new(Counting::Ti1Only, 99, [true, false, false]);
    assert_eq!(e.input(true, true), No); // TI2 rising, TI1 high: up in the both-inputs rows
    assert!(!e.dir_down());
    assert_eq!(e.input(true, false), No); // TI2 falling, TI1 high: down
    assert!(e.dir_down());
}

// The table assumes "TI1 and TI2 do not switch at the same time".
#[test]
#[should_panic(expected = "same time")]
fn both_inputs_switching_together_is_refused() {
    Encoder::new(Counting::Both, 99, [false; 3]).input(true, true);
}

// §13.3.5: at TI3's active (rising, CC3P = 0) edge CCR3 takes the counter, CC3IF is set,
// CC3OF too if CC3IF had not been cleared; reading CCR3 clears CC3IF (§13.4.5).
#[test]
fn the_index_rising_edge_captures_the_count() {
    let mut e = Encoder::new(Counting::Both, 0xFFFF, [false; 3]);
    walk(&mut e, &[(1, 0), (1, 1)]);
    e.index(true);
    walk(&mut e, &[(0, 1)]);
    e.index(false);
    assert_eq!(e.take_capture(), Some(2));
    assert_eq!(e.take_capture(), None);
    assert!(!e.overcaptured());
    e.index(true);
    e.index(false);
    e.index(true);
    assert_eq!(e.take_capture(), Some(3));
    assert!(e.overcaptured());
}
