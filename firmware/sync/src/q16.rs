//! Q16 fixed point, the core's unit for positions and speeds: steps (or
//! counts) with 16 fraction bits in an `i64`, so sums and differences are
//! plain integer adds and a tick's arithmetic stays in 64 bits. Written
//! here rather than taken from the `fixed` crate: a `fixed` product widens
//! to 128 bits, which cost the tick 24 to 26 instructions on an emulated Cortex-M4, and the
//! values cross the core's interfaces as plain `i64` (docs/src/fixed-point.md).

/// One half, in Q16.
pub const HALF: i64 = 1 << 15;

/// `x` rounded to whole units, a half rounding up (1.5 → 2, −1.5 → −1):
/// the step a commanded position stands nearest, the same either side of
/// zero.
#[inline(always)]
pub const fn round(x: i64) -> i64 {
    (x + HALF) >> 16
}

/// Whole `steps` (or counts) in Q16.
#[inline(always)]
pub const fn from_steps(steps: i64) -> i64 {
    steps << 16
}

/// The product of two Q16 values, rounded down, in 64 bits: the caller
/// keeps |a·b| under 2^63 (a `fixed` product widens to 128 bits instead).
#[inline(always)]
pub const fn mul(a: i64, b: i64) -> i64 {
    (a * b) >> 16
}

/// Limits `x` to ±`limit` (0 ≤ `limit` < 2^62) without the panic path of
/// `clamp` (which asserts min ≤ max): the control tick has no reachable
/// panic. Inside is one unsigned compare (x + limit ≤ 2·limit), the common
/// case: on the Cortex-M4 two signed 64-bit selects cost the tick about
/// 14 instructions a call against 7 (counted on an emulated Cortex-M4).
#[inline(always)]
pub fn bound(x: i64, limit: i64) -> i64 {
    if !beyond(x, limit) {
        x
    } else if x < 0 {
        -limit
    } else {
        limit
    }
}

/// |`x`| > `limit` (0 ≤ `limit` < 2^62), as one unsigned compare: x +
/// limit falls outside [0, 2·limit] exactly then (below 0 it wraps high).
/// An `abs` and a signed 64-bit compare cost the tick twice as much.
#[inline(always)]
pub fn beyond(x: i64, limit: i64) -> bool {
    (x.wrapping_add(limit) as u64) > (2 * limit) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_is_half_a_unit() {
        assert_eq!(HALF * 2, from_steps(1));
    }

    #[test]
    fn round_takes_the_nearest_whole_unit_and_a_half_up() {
        let q = |units: f64| (units * 65536.0) as i64;
        assert_eq!(round(q(2.49)), 2);
        assert_eq!(round(q(2.5)), 3);
        assert_eq!(round(q(2.51)), 3);
        assert_eq!(round(q(-1.5)), -1);
        assert_eq!(round(q(-1.51)), -2);
        assert_eq!(round(q(-0.49)), 0);
        assert_eq!(round(HALF - 1), 0);
        assert_eq!(round(-HALF - 1), -1);
    }

    #[test]
    fn from_steps_is_exact_both_ways() {
        assert_eq!(from_steps(3), 3 * 65536);
        assert_eq!(from_steps(-7), -7 * 65536);
        assert_eq!(round(from_steps(-7)), -7);
        assert_eq!(from_steps(0), 0);
    }

    #[test]
    fn mul_keeps_sixteen_fraction_bits_and_rounds_down() {
        assert_eq!(mul(from_steps(3), from_steps(5)), from_steps(15));
        assert_eq!(mul(HALF, HALF), from_steps(1) / 4);
        assert_eq!(mul(from_steps(-2), HALF + from_steps(1)), from_steps(-3));
        assert_eq!(mul(1, 1), 0, "2^-32 rounds down to 0");
        assert_eq!(mul(-1, 1), -1, "−2^-32 rounds down to −2^-16");
        assert_eq!(mul(3, 1 << 16), 3);
    }

    #[test]
    fn beyond_is_a_magnitude_past_the_limit() {
        for limit in [0i64, 1, 4, 1 << 40, (1 << 62) - 1] {
            for x in [0i64, 1, -1, limit, -limit, limit + 1, -limit - 1, i64::MAX, i64::MIN, i64::MIN + 1] {
                assert_eq!(beyond(x, limit), x.unsigned_abs() > limit as u64, "{x} against {limit}");
            }
        }
    }

    #[test]
    fn bound_limits_both_ways_and_keeps_what_is_inside() {
        assert_eq!(bound(10, 4), 4);
        assert_eq!(bound(-10, 4), -4);
        assert_eq!(bound(3, 4), 3);
        assert_eq!(bound(-3, 4), -3);
        assert_eq!(bound(4, 4), 4);
        assert_eq!(bound(-4, 4), -4);
        assert_eq!(bound(i64::MAX, 4), 4);
        assert_eq!(bound(i64::MIN, 4), -4);
        assert_eq!(bound(i64::MIN + 3, 4), -4);
        assert_eq!(bound(7, 0), 0);
        assert_eq!(bound(-7, 0), 0);
        assert_eq!(bound(-7, 1 << 61), -7);
    }
}
