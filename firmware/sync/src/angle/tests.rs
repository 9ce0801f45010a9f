use super::*;
use std::string::{String, ToString};

fn text(f: Fixed) -> String {
    f.to_string()
}

#[test]
fn degrees_have_the_fewest_decimals_that_still_tell_two_counts_apart() {
    for (cpr, d) in
        [(4, 0), (360, 0), (361, 1), (2400, 1), (3600, 1), (3601, 2), (36_000, 2), (360_000, 3), (1_000_000, 4)]
    {
        assert_eq!(decimals(cpr), d, "cpr {cpr}");
    }
    // a count of 2400 is 0.15 degrees: each count reads apart at one decimal
    let read: std::vec::Vec<String> = (0..8).map(|c| text(Angle::of(c, None, 2400).degrees())).collect();
    assert_eq!(read, ["0.0", "0.2", "0.3", "0.5", "0.6", "0.8", "0.9", "1.1"]);
    assert_eq!(text(Angle::of(2399, None, 2400).degrees()), "359.9");
    assert_eq!(text(Angle::of(1, None, 1_000_000).degrees()), "0.0004");
    assert_eq!(text(Angle::of(7, None, 360).degrees()), "7");
}

#[test]
fn before_an_index_the_angle_is_from_the_start_and_after_it_from_the_index() {
    let start = Angle::of(2401, None, 2400);
    assert_eq!(start, Angle { counts: 1, cpr: 2400, from_index: false });
    let indexed = Angle::of(1005 + 1200, Some(1005), 2400);
    assert_eq!(indexed, Angle { counts: 1200, cpr: 2400, from_index: true });
    assert_eq!(text(indexed.degrees()), "180.0");
}

#[test]
fn turned_back_past_the_origin_the_angle_stays_within_a_turn() {
    assert_eq!(Angle::of(-1, None, 2400).counts, 2399, "back a count from the start");
    assert_eq!(Angle::of(1004, Some(1005), 2400).counts, 2399, "back a count from the index");
    assert_eq!(Angle::of(-10 * 2400 + 1005 + 600, Some(1005), 2400).counts, 600, "ten turns back");
    assert_eq!(Angle::of(7 * 2400 + 1005 + 600, Some(1005), 2400).counts, 600, "seven turns on");
}

fn division(counts: u32, cpr: u32, n: u32) -> Division {
    Division::of(&Angle { counts, cpr, from_index: true }, n)
}

/// (number, at degrees, to degrees, to counts, within)
fn shown(d: Division) -> (u32, String, String, String, bool) {
    (d.number, text(d.at_degrees()), text(d.to_degrees()), text(d.to_counts()), d.within())
}

#[test]
fn the_nearest_division_and_the_way_to_it_within_one_count() {
    let s = |n: u32, a: &str, t: &str, c: &str, w: bool| (n, a.to_string(), t.to_string(), c.to_string(), w);
    // six of 400 counts
    assert_eq!(shown(division(0, 2400, 6)), s(0, "0.0", "0.0", "0.00", true));
    assert_eq!(shown(division(399, 2400, 6)), s(1, "60.0", "0.2", "1.00", true));
    assert_eq!(shown(division(398, 2400, 6)), s(1, "60.0", "0.3", "2.00", false));
    assert_eq!(shown(division(402, 2400, 6)), s(1, "60.0", "-0.3", "-2.00", false));
    assert_eq!(shown(division(2399, 2400, 6)), s(0, "0.0", "0.2", "1.00", true), "the last count before the origin");
    // half-way between two, the next one up
    assert_eq!(shown(division(200, 2400, 6)), s(1, "60.0", "30.0", "200.00", false));
    assert_eq!(shown(division(2200, 2400, 6)), s(0, "0.0", "30.0", "200.00", false));
}

#[test]
fn a_division_between_two_counts_is_exact_and_both_neighbours_are_within() {
    let s = |n: u32, a: &str, t: &str, c: &str, w: bool| (n, a.to_string(), t.to_string(), c.to_string(), w);
    // seven: division 1 at 342 6/7 counts, 51 3/7 degrees
    assert_eq!(shown(division(343, 2400, 7)), s(1, "51.4", "0.0", "-0.14", true));
    assert_eq!(shown(division(342, 2400, 7)), s(1, "51.4", "0.1", "0.86", true));
    assert_eq!(shown(division(344, 2400, 7)), s(1, "51.4", "-0.2", "-1.14", false));
    assert_eq!(shown(division(341, 2400, 7)), s(1, "51.4", "0.3", "1.86", false));
}

#[test]
fn one_division_is_the_origin_from_either_side() {
    assert_eq!(division(1300, 2400, 1).number, 0);
    assert_eq!(text(division(1300, 2400, 1).to_counts()), "1100.00");
    assert_eq!(text(division(1100, 2400, 1).to_counts()), "-1100.00");
    assert_eq!(text(division(1100, 2400, 1).to_degrees()), "-165.0");
}

#[test]
fn a_fixed_rounds_half_away_from_zero_and_has_no_sign_at_zero() {
    let f = |num: i64, den: i64, decimals: u32| text(Fixed { num, den, decimals });
    assert_eq!([f(1, 2, 0), f(-1, 2, 0), f(1, 3, 0), f(-1, 3, 0)], ["1", "-1", "0", "0"]);
    assert_eq!([f(4, 1000, 2), f(-4, 1000, 2), f(-5, 1000, 2), f(-1, 1, 2)], ["0.00", "0.00", "-0.01", "-1.00"]);
    assert_eq!(f(-360_000, 7, 3), "-51428.571");
}
