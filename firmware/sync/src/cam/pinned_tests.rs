//! Fixed walks of a small cam, with positions worked out by hand: 4 points
//! over 8 counts, so every count is a segment's start or middle and the
//! linear interpolation is exact in Q16 (the property tests compare
//! random walks with a float model, within its rounding).

use super::*;

static TABLE: [i32; 4] = [500, 1_000, 3_000, -2_000];

/// The table's value at count `c` (period 8): points at even counts,
/// midpoints at odd ones, back to the first point after the last.
fn by_hand(c: i64) -> i64 {
    const AT: [i64; 8] = [500, 750, 1_000, 2_000, 3_000, 500, -2_000, -750];
    AT[c.rem_euclid(8) as usize] << 16
}

#[test]
fn walking_count_by_count_both_ways_lands_on_every_point_and_midpoint() {
    let mut cam = Cam::new(&TABLE, 8).unwrap();
    assert_eq!(cam.period(), 8);
    for c in 1..=17 {
        cam.advance(1);
        assert_eq!(cam.position_q16(0), by_hand(c), "forward to {c}");
    }
    for c in (-9..17).rev() {
        cam.advance(-1);
        assert_eq!(cam.position_q16(0), by_hand(c), "back to {c}");
    }
}

#[test]
fn ticks_of_several_counts_land_where_single_counts_do() {
    let mut cam = Cam::new(&TABLE, 8).unwrap();
    let mut c = 0i64;
    for d in [3, 5, -7, -4, 9, 2, -1, -13] {
        cam.advance(d);
        c += d as i64;
        assert_eq!(cam.position_q16(0), by_hand(c), "at {c}");
    }
}

#[test]
fn seek_goes_to_any_count_either_side_of_zero() {
    let mut cam = Cam::new(&TABLE, 8).unwrap();
    for c in -20..20 {
        cam.seek(c);
        assert_eq!(cam.position_q16(0), by_hand(c), "{c}");
        // and walks on from there
        cam.advance(1);
        assert_eq!(cam.position_q16(0), by_hand(c + 1), "{c} + 1");
    }
}

#[test]
fn a_sub_count_offset_interpolates_within_the_segment() {
    let mut cam = Cam::new(&TABLE, 8).unwrap();
    cam.seek(1); // the middle of 500 → 1000
    assert_eq!(cam.position_q16(1 << 15), 875 << 16, "half a count on");
    assert_eq!(cam.position_q16(-(1 << 15)), 625 << 16, "half a count back");
    cam.seek(5); // the middle of 3000 → −2000
    assert_eq!(cam.position_q16(1 << 15), -750 << 16);
    cam.seek(7); // the middle of −2000 → 500, the segment over the wrap
    assert_eq!(cam.position_q16(1 << 15), -125 << 16);
}

#[test]
fn the_table_limits_count_the_wrap_and_the_size() {
    // a table standing at 2^22 has no step at all
    let high: &'static [i32] = std::vec::Vec::leak(std::vec![1 << 22; 3]);
    assert!(Cam::new(high, 3).is_ok());
    // from −2^22 to 2^22 is a step of 2^23, on the way and on the wrap
    assert_eq!(Cam::check(&[-(1 << 22), 1 << 22], 2), Err(CamError::Step));
    assert_eq!(Cam::check(&[1 << 22, 0, -(1 << 22)], 3), Err(CamError::Step), "on the wrap only");
    let full = std::vec![0; CAM_POINTS];
    assert_eq!(Cam::check(&full, CAM_POINTS as u32), Ok(()));
    let over = std::vec![0; CAM_POINTS + 1];
    assert_eq!(Cam::check(&over, 2_000), Err(CamError::Points));
}
