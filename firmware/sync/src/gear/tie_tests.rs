//! Exact half-step ties, walked one count at a time both ways: the gear
//! rounds half up (toward +∞) and keeps −den ≤ rem2 < den, so a tie reads
//! rem2 = −den whichever way the lathe came. Fixed cases the random walks
//! rarely reach (a tie needs an even denominator and a count landing on it).

use super::*;

/// `count · num / den` rounded half up, and 2·count·num − 2·steps·den.
fn exact(s: Scale, count: i64) -> (i64, i64) {
    let twice = 2 * count * s.num as i64;
    let steps = (twice + s.den as i64).div_euclid(2 * s.den as i64);
    (steps, twice - 2 * steps * s.den as i64)
}

#[test]
fn half_a_step_a_count_rounds_every_tie_up_walking_back_and_forth() {
    let s = Scale { num: 1, den: 2 };
    let mut g = Gear::new(s);
    // back from 0: −½ → 0, −1 → −1, −1½ → −1, −2 → −2 ...
    for count in (-9i64..0).rev() {
        g.advance(-1);
        assert_eq!((g.count(), g.steps(), g.rem2()), (count, exact(s, count).0, exact(s, count).1), "back to {count}");
    }
    assert_eq!((g.steps(), g.rem2()), (-4, -2), "−4½ is −4 with rem2 = −den");
    for count in -8i64..=9 {
        g.advance(1);
        assert_eq!((g.count(), g.steps(), g.rem2()), (count, exact(s, count).0, exact(s, count).1), "on to {count}");
    }
    assert_eq!((g.steps(), g.rem2()), (5, -2), "4½ is 5 with rem2 = −den");
}

#[test]
fn three_halves_a_count_ties_on_odd_counts_in_multi_count_ticks() {
    // ticks of several counts each way (the tick's `delta`)
    let s = Scale { num: 3, den: 2 };
    let mut g = Gear::new(s);
    let mut count = 0i64;
    for d in [-1, -2, -3, 5, -7, 4, 1, -1, -1, -1] {
        g.advance(d);
        count += d as i64;
        assert_eq!((g.steps(), g.rem2()), exact(s, count), "at {count}");
        assert!(-2 <= g.rem2() && g.rem2() < 2);
    }
    // −3 counts is −4½ steps: −4
    let mut g = Gear::new(s);
    g.advance(-3);
    assert_eq!((g.steps(), g.rem2()), (-4, -2));
    g.advance(3);
    assert_eq!((g.steps(), g.rem2()), (0, 0));
}

#[test]
fn a_reset_onto_a_tie_agrees_with_walking_onto_it() {
    let s = Scale { num: 5, den: 2 };
    for count in [-3i64, -1, 1, 3] {
        let mut reset = Gear::new(s);
        reset.reset(count);
        let mut walked = Gear::new(s);
        walked.advance(count as i32);
        assert_eq!((reset.steps(), reset.rem2()), (walked.steps(), walked.rem2()), "{count}");
        assert_eq!(reset.rem2(), -2, "{count}: every odd count is a tie");
    }
}
