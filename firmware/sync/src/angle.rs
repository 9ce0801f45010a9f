//! The spindle's angle and the divisions of a turn (`divide N`), from the
//! lathe's count: exact integers, degrees only as they are written. Low
//! priority (`status`): it divides.
//!
//! The angle is counted the way the lathe's encoder counts up (as
//! `lathe_rpm` is positive), within one turn, from an origin:
//! * from the index, once one has been seen: the count the encoder timer
//!   latched at the first index pulse since the board started (TIM3's
//!   capture on the index's rising edge, RM0383 §13.3.6). The index is a
//!   mark on the spindle, so this origin is the same after a reset once
//!   the spindle has passed the index again. Passed the other way, the
//!   pulse may latch up to its width (about a count) further on;
//! * before that, from the count at the board's start (`angle_from=start`):
//!   wherever the spindle stood then, so not the same after a reset.
//!
//! Division k of N is at k·cpr/N counts from the origin; the spindle is
//! shown against the nearest one, within `TOLERANCE_COUNTS` of it or not.

use core::fmt;

/// How far from a division still counts as on it: one count each way,
/// the least the encoder can resolve on either side of a division that
/// falls between two counts.
pub const TOLERANCE_COUNTS: i64 = 1;

/// The spindle's angle: counts from the origin within one turn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Angle {
    /// 0..cpr
    pub counts: u32,
    pub cpr: u32,
    /// the origin is the index (else the count at the board's start)
    pub from_index: bool,
}

impl Angle {
    /// The angle of the lathe at `lathe_counts`, with the index latched at
    /// `index_counts` if one has been seen, on an encoder of `cpr` counts a
    /// turn.
    pub fn of(lathe_counts: i64, index_counts: Option<i64>, cpr: u32) -> Angle {
        let cpr = cpr.max(1);
        let from = index_counts.unwrap_or(0);
        let counts = (lathe_counts - from).rem_euclid(cpr as i64) as u32;
        Angle { counts, cpr, from_index: index_counts.is_some() }
    }

    /// In degrees, to the encoder's resolution (`decimals`).
    pub fn degrees(&self) -> Fixed {
        Fixed::degrees(self.counts as i64, 1, self.cpr)
    }
}

/// The decimals degrees are written with on an encoder of `cpr` counts a
/// turn: the fewest whose last digit is no more than a count (360/cpr
/// degrees), so two counts never read the same and no digit is invented.
pub const fn decimals(cpr: u32) -> u32 {
    let (mut d, mut counts_per_unit) = (0, 360u64);
    while (cpr as u64) > counts_per_unit {
        d += 1;
        counts_per_unit *= 10;
    }
    d
}

/// The spindle against N divisions of a turn: the nearest division and
/// the way to it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Division {
    pub divisions: u32,
    /// the nearest division, 0..divisions
    pub number: u32,
    /// the division's place less the spindle's, counts × divisions (exact:
    /// a division may fall between two counts); positive: turn the way
    /// the count goes up
    to_scaled: i64,
    cpr: u32,
}

impl Division {
    /// The division nearest `angle` among `divisions` (at least 1).
    pub fn of(angle: &Angle, divisions: u32) -> Division {
        let (n, cpr) = (divisions.max(1) as i64, angle.cpr as i64);
        // the division at or past the angle's place, half-way going up:
        // round(counts · n / cpr); n there is the origin again, a turn on
        let scaled = angle.counts as i64 * n;
        let nearest = (2 * scaled + cpr) / (2 * cpr);
        Division {
            divisions: n as u32,
            number: (nearest % n) as u32,
            to_scaled: nearest * cpr - scaled,
            cpr: angle.cpr,
        }
    }

    /// The division's angle from the origin, degrees.
    pub fn at_degrees(&self) -> Fixed {
        let n = self.divisions as i64;
        Fixed { num: self.number as i64 * 360, den: n, decimals: decimals(self.cpr) }
    }

    /// How far to turn to it, degrees (positive: the way the count goes up).
    pub fn to_degrees(&self) -> Fixed {
        Fixed::degrees(self.to_scaled, self.divisions as i64, self.cpr)
    }

    /// How far to turn to it, counts, in hundredths.
    pub fn to_counts(&self) -> Fixed {
        Fixed { num: self.to_scaled, den: self.divisions as i64, decimals: 2 }
    }

    /// Within `TOLERANCE_COUNTS` of it.
    pub fn within(&self) -> bool {
        self.to_scaled.abs() <= TOLERANCE_COUNTS * self.divisions as i64
    }
}

/// A fraction written with a fixed number of decimals, rounded half away
/// from zero; no sign when it rounds to zero. Within 64 bits (no 128-bit
/// division or formatting in the image): a numerator is at most a turn's
/// counts × 360 (3.6e8 at the largest cpr), × 2 × 10^4 for its decimals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fixed {
    num: i64,
    den: i64,
    decimals: u32,
}

impl Fixed {
    /// `counts / per` counts of an encoder of `cpr`, in degrees to its
    /// resolution.
    fn degrees(counts: i64, per: i64, cpr: u32) -> Fixed {
        Fixed { num: counts * 360, den: per * cpr.max(1) as i64, decimals: decimals(cpr) }
    }
}

impl fmt::Display for Fixed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let unit = 10u64.pow(self.decimals);
        let den = self.den.max(1) as u64;
        // |num| · 10^d rounded half away from zero, in units of the last digit
        let units = (2 * self.num.unsigned_abs() * unit + den) / (2 * den);
        let sign = if self.num < 0 && units != 0 { "-" } else { "" };
        let (whole, frac) = (units / unit, units % unit);
        match self.decimals {
            0 => write!(f, "{sign}{whole}"),
            d => write!(f, "{sign}{whole}.{frac:0width$}", width = d as usize),
        }
    }
}

#[cfg(test)]
mod tests;
