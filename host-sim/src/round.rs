//! `floor` and `ceil` for the simulator's hot loops. The x86-64 baseline
//! has no rounding instruction (SSE4.1's `roundsd`), so `f64::floor` is a
//! library call: a few of them a tick were a tenth of the simulator's time.
//! These truncate through an integer instead: the same value for every
//! finite input (an f64 of magnitude 2^52 or more is already whole), and
//! NaN and the infinities pass through as they are.

/// Largest magnitude below which an f64 can have a fraction.
const WHOLE: f64 = 4_503_599_627_370_496.0; // 2^52

#[inline]
pub fn floor(x: f64) -> f64 {
    // (whole already, or NaN or infinite: as it is)
    if x.abs() >= WHOLE || x.is_nan() {
        return x;
    }
    // SAFETY: finite and below 2^52 in magnitude (tested above), so in
    // i64's range: the plain truncating conversion, without the checks an
    // `as` cast adds for NaN and out-of-range values (a third of the cost)
    let t = unsafe { x.to_int_unchecked::<i64>() } as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

#[inline]
pub fn ceil(x: f64) -> f64 {
    -floor(-x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal to the library's for fractions, whole numbers, halves, the
    /// edges of the range and beyond (zero's sign aside: no caller asks).
    #[test]
    fn floor_and_ceil_match_the_librarys() {
        let mut xs = vec![0.0, 0.5, -0.5, 1.0, -1.0, 2.5, -2.5, 1e-300, -1e-300, 0.999_999_999_999_9, -7.000_000_000_1];
        xs.extend([WHOLE - 0.5, -(WHOLE - 0.5), WHOLE, -WHOLE, 1e300, -1e300, f64::INFINITY, f64::NEG_INFINITY]);
        let mut v = 0.123_456_789f64;
        for _ in 0..10_000 {
            v = (v * 7_919.0 + 0.317).sin() * 1e6;
            xs.push(v);
            xs.push(v / 1e6);
        }
        for x in xs {
            assert_eq!(floor(x), x.floor(), "floor {x}");
            assert_eq!(ceil(x), x.ceil(), "ceil {x}");
        }
        assert!(floor(f64::NAN).is_nan() && ceil(f64::NAN).is_nan());
    }
}
