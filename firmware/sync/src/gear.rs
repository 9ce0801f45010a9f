//! The exact gear: lathe counts → motor steps, rounded, with no drift ever.
//!
//! motor target = count × p·M / (q·E). Kept as a
//! Bresenham/DDA pair (steps, rem2) with the invariant
//!
//!   2·count·num = 2·steps·den + rem2,   −den ≤ rem2 < den,
//!
//! so `steps` is always the exact rounding (half up) of the rational target.
//! The per-count step is precomputed with one division when the scale is set
//! (at low priority); the tick adds, compares and multiplies.

/// Motor steps per lathe count as an exact fraction num/den.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Scale {
    pub num: u64,
    pub den: u64,
}

impl Scale {
    /// p·M / (q·E), reduced. `None` if a term is zero.
    pub fn new(p: u32, q: u32, motor_per_rev: u32, counts_per_rev: u32) -> Option<Scale> {
        let (num, den) = (p as u64 * motor_per_rev as u64, q as u64 * counts_per_rev as u64);
        if num == 0 || den == 0 {
            return None;
        }
        let g = crate::ratio::gcd(num, den);
        Some(Scale { num: num / g, den: den / g })
    }

    /// The exact rounded target for an absolute count (uses 128-bit
    /// division: for setup, tests and the reference model, never the tick).
    pub fn round(self, count: i64) -> i64 {
        // 64 bits when they suffice (every count a lathe reaches in years):
        // a 128-bit division costs about 1 000 instructions on the M4, and
        // a re-base runs under the tick's lock
        let fits = |v: i64| i64::try_from(self.num).ok().and_then(|n| v.checked_mul(n));
        if let (Some(p), Ok(den)) = (fits(count), i64::try_from(self.den)) {
            if let Some(twice) = p.checked_mul(2).and_then(|t| t.checked_add(den)) {
                return twice.div_euclid(2 * den);
            }
        }
        let twice = 2 * count as i128 * self.num as i128 + self.den as i128;
        twice.div_euclid(2 * self.den as i128) as i64
    }
}

/// The running DDA. `advance` is the control-tick path.
#[derive(Clone, Copy, Debug)]
pub struct Gear {
    scale: Scale,
    /// whole steps per count and the remainder, ×2 (for rounding)
    q: i64,
    r2: i64,
    den2: i64,
    count: i64,
    steps: i64,
    rem2: i64,
}

impl Gear {
    pub fn new(scale: Scale) -> Gear {
        let mut g = Gear {
            scale,
            q: (scale.num / scale.den) as i64,
            r2: 2 * (scale.num % scale.den) as i64,
            den2: 2 * scale.den as i64,
            count: 0,
            steps: 0,
            rem2: 0,
        };
        g.reset(0);
        g
    }

    /// Re-bases at an absolute count (low priority: one 128-bit division).
    pub fn reset(&mut self, count: i64) {
        self.count = count;
        self.steps = self.scale.round(count);
        // the remainder is below 2·den in magnitude: wrapping 64-bit
        // products give it exactly (both sides agree modulo 2^64)
        let exact2 = count.wrapping_mul(2).wrapping_mul(self.scale.num as i64);
        self.rem2 = exact2.wrapping_sub(self.steps.wrapping_mul(2).wrapping_mul(self.scale.den as i64));
    }

    /// Moves by `delta` counts: the whole steps and the remainder of
    /// `delta` counts at once (a multiply each), then a carry each time
    /// the remainder reaches den or falls below −den (at most |`delta`|
    /// of them, as 0 ≤ r2 < den2): no division. Taking the counts one at
    /// a time cost the tick about 30 instructions more on average
    /// (counted on an emulated Cortex-M4).
    ///
    /// For |`delta`| · 2·den and |`delta`| · steps per count under 2^62:
    /// a tick's counts (at most 16 000, the plausibility check's bound)
    /// with any scale a valid setting makes (den under 2^30).
    /// `advance_many` takes any stride.
    #[inline]
    pub fn advance(&mut self, delta: i32) {
        let half = self.den2 >> 1; // a shift: no 64-bit division on the tick
        let n = delta as i64;
        debug_assert!(
            (delta.unsigned_abs() as u128) * (self.den2.max(self.q) as u128) < 1 << 62,
            "a stride past advance's range: advance_many takes it"
        );
        self.steps += n * self.q;
        self.rem2 += n * self.r2;
        // The carries: forward counts only raise the remainder and backward
        // ones only lower it, so one branch runs, at most |delta| times.
        for _ in 0..delta.unsigned_abs() {
            if self.rem2 >= half {
                self.rem2 -= self.den2;
                self.steps += 1;
            } else if self.rem2 < -half {
                self.rem2 += self.den2;
                self.steps -= 1;
            } else {
                break;
            }
        }
        self.count += n;
    }

    /// Moves by many counts at once with the same invariant (128-bit
    /// arithmetic): the fast path for long-run tests and re-synchronising,
    /// never the tick.
    pub fn advance_many(&mut self, delta: i64) {
        let total = self.rem2 as i128 + delta as i128 * self.r2 as i128 + self.den2 as i128 / 2;
        let carry = total.div_euclid(self.den2 as i128);
        self.rem2 = (total.rem_euclid(self.den2 as i128) - self.den2 as i128 / 2) as i64;
        self.steps += delta * self.q + carry as i64;
        self.count += delta;
    }

    pub fn count(&self) -> i64 {
        self.count
    }
    /// The exact rounded target in whole steps.
    pub fn steps(&self) -> i64 {
        self.steps
    }
    /// Twice the rounding remainder in units of 1/den step: [−den, den).
    pub fn rem2(&self) -> i64 {
        self.rem2
    }
    pub fn scale(&self) -> Scale {
        self.scale
    }
}

#[cfg(test)]
mod stride_tests;
#[cfg(test)]
mod tie_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn a_third_of_a_step_per_count_rounds_half_up() {
        let mut g = Gear::new(Scale { num: 1, den: 3 });
        let seen: [i64; 7] = core::array::from_fn(|_| {
            let s = g.steps();
            g.advance(1);
            s
        });
        assert_eq!(seen, [0, 0, 1, 1, 1, 2, 2]);
        g.advance(-7);
        assert_eq!((g.count(), g.steps()), (0, 0));
    }

    proptest! {
        #[test]
        fn the_64_bit_rounding_and_reset_agree_with_128_bits(
            p in 1u32..=1000, q in 1u32..=1000, m in 1u32..=100_000, e in 1u32..=65_536,
            count in prop_oneof![-1_000_000i64..1_000_000, i64::MIN / 2..i64::MAX / 2],
        ) {
            let scale = Scale::new(p, q, m, e).unwrap();
            let twice = 2 * count as i128 * scale.num as i128 + scale.den as i128;
            let exact = twice.div_euclid(2 * scale.den as i128);
            prop_assume!(i64::try_from(exact).is_ok());
            prop_assert_eq!(scale.round(count) as i128, exact);
            let mut g = Gear::new(scale);
            g.reset(count);
            let rem2 = 2 * count as i128 * scale.num as i128 - 2 * exact * scale.den as i128;
            prop_assert_eq!(g.rem2() as i128, rem2);
        }

        #[test]
        fn any_walk_lands_on_the_exact_rounding(
            p in 1u32..=1000, q in 1u32..=1000, m in 1u32..=100_000, e in 1u32..=65_536,
            start in -1_000_000i64..1_000_000,
            walk in proptest::collection::vec(-40i32..=40, 0..400),
        ) {
            let scale = Scale::new(p, q, m, e).unwrap();
            let mut g = Gear::new(scale);
            g.reset(start);
            let mut count = start;
            for d in walk {
                g.advance(d);
                count += d as i64;
                prop_assert_eq!(g.steps(), scale.round(count));
                prop_assert!(-(scale.den as i64) <= g.rem2() && g.rem2() < scale.den as i64);
            }
        }

        #[test]
        fn no_drift_over_ten_billion_counts(
            p in 1u32..=1000, q in 1u32..=1000, m in 200u32..=51_200,
            chunks in proptest::collection::vec(2_000_000_000i64..2_100_000_000, 5..=5),
        ) {
            // A day of running in big strides (the fast path), with tick-sized
            // walks between them, forward then back to the start.
            let scale = Scale::new(p, q, m, 2400).unwrap();
            let mut g = Gear::new(scale);
            let mut count = 0i64;
            for c in &chunks {
                g.advance_many(*c);
                for _ in 0..50 { g.advance(3); }
                count += c + 150;
                prop_assert_eq!(g.steps(), scale.round(count));
            }
            g.advance_many(-count + 150 * 5);
            for _ in 0..50 * 5 { g.advance(-3); }
            prop_assert_eq!((g.count(), g.steps()), (0, 0));
        }
    }
}
