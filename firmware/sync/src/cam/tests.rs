use super::*;
use proptest::prelude::*;

/// Reference model: linear interpolation of the table at count c, in f64.
fn reference(points: &[i32], period: u32, c: i64) -> f64 {
    let n = points.len() as f64;
    let phase = c.rem_euclid(period as i64) as f64 / period as f64 * n;
    let i = phase.floor() as usize;
    let f = phase - i as f64;
    let (a, b) = (points[i % points.len()] as f64, points[(i + 1) % points.len()] as f64);
    a + (b - a) * f
}

proptest! {
    #[test]
    fn any_walk_matches_the_reference_and_returns_exactly(
        points in proptest::collection::vec(-100_000i32..100_000, 2..64),
        extra in 0u32..20_000,
        walk in proptest::collection::vec(-30i32..=30, 1..300),
    ) {
        let period = points.len() as u32 + extra;
        let points: &'static [i32] = std::vec::Vec::leak(points);
        let mut cam = Cam::new(points, period).unwrap();
        let start = cam.position_q16(0);
        let mut c = 0i64;
        for d in &walk {
            cam.advance(*d);
            c += *d as i64;
            let got = cam.position_q16(0) as f64 / 65536.0;
            // Q24 fraction: within span / 2^24 (+ Q16 rounding) of the reference
            let span = points.windows(2).map(|w| (w[1] - w[0]).abs()).max().unwrap_or(0)
                .max((points[0] - points[points.len() - 1]).abs()) as f64;
            // The Q24 fraction floors (≤ 1 + acc/2^16 < 2 units of the span)
            // and the Q16 product floors toward −∞ (≤ 4 units).
            let tol = 2.0 * span / (1u64 << 24) as f64 + 4.0 / 65536.0;
            prop_assert!((got - reference(points, period, c)).abs() <= tol, "count {}: {} vs {}", c, got, reference(points, period, c));
        }
        // The lathe goes back to where it started: the cam is exactly there.
        cam.advance(-(c as i32));
        prop_assert_eq!(cam.position_q16(0), start);
    }

    #[test]
    fn seek_agrees_with_advancing(points in proptest::collection::vec(-1000i32..1000, 2..32), c in -100_000i64..100_000) {
        let period = 2400u32;
        let points: &'static [i32] = std::vec::Vec::leak(points);
        let (mut walked, mut sought) = (Cam::new(points, period).unwrap(), Cam::new(points, period).unwrap());
        let mut left = c;
        while left != 0 {
            let d = left.clamp(-1000, 1000) as i32;
            walked.advance(d);
            left -= d as i64;
        }
        sought.seek(c);
        prop_assert_eq!(walked.position_q16(0), sought.position_q16(0));
    }
}

#[test]
fn sub_count_offset_interpolates_between_counts() {
    let cam = Cam::new(&[0, 2400], 2400).unwrap(); // 1 step per count on the way up
    assert_eq!(cam.position_q16(1 << 15) >> 15, 1); // half a count: half a step
}

#[test]
fn bad_tables_are_refused() {
    assert_eq!(Cam::new(&[1], 100).unwrap_err(), CamError::Points);
    assert_eq!(Cam::new(&[1, 2, 3], 2).unwrap_err(), CamError::Period);
    assert_eq!(Cam::new(&[0, 1 << 23], 100).unwrap_err(), CamError::Step);
}
