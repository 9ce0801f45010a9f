//! What a cam table asks of its X axis once the lathe turns. The X
//! position is linear between the points, so the steepest step between
//! neighbours is a speed and the sharpest bend an acceleration, both in
//! proportion to the lathe's speed (its square). The header declares the X
//! axis (`max_rate_hz`, `max_accel`) and the encoder the points are spaced
//! on (`counts_per_rev`, which must be the board's `cpr`,
//! `Controller::check_cam`). A table its own axis cannot follow even at
//! the slowest lathe speed a cut takes, [`SLOWEST_RPM`] (`polyturn cam
//! --rpm`'s floor), is one no cut can use (a slip of the steps per mm, a
//! table for another machine): it is refused before it is stored.
//!
//! The points are whole steps, each within half a step of its path, so a
//! step's difference between neighbours (two in a bend) is the rounding's,
//! not motion: it is allowed for. A dense table moves a step or less
//! between neighbours, all of it within that allowance, so the motion is
//! also measured over spans of 2, 4, 8 … segments: over k segments the
//! path moves at least the points' difference less one step, and bends
//! (its second difference at spacing k) at least theirs less two, in k
//! times the time (k² for a bend). Each span gives a lower bound of the
//! speed and acceleration the path needs; the largest is checked.

use super::CamHeader;

/// The slowest lathe speed a table must be followed at, rpm.
pub const SLOWEST_RPM: u64 = 1;

/// A table its X axis cannot follow at [`SLOWEST_RPM`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MotionError {
    /// points `span` segments apart, `apart` steps apart, need `needs_hz`
    /// X steps/s, beyond the header's `max_hz`
    Rate { span: u32, apart: u32, needs_hz: u64, max_hz: u32 },
    /// a bend of `bend` steps (the second difference at spacing `span`)
    /// needs `needs` X steps/s², beyond the header's `max`
    Accel { span: u32, bend: u32, needs: u64, max: u32 },
}

impl MotionError {
    /// The reason without its figures (the stored table's check at boot).
    pub fn describe(self) -> &'static str {
        match self {
            MotionError::Rate { .. } => "cam table: its points need more than its max-rate even at 1 lathe rpm",
            MotionError::Accel { .. } => "cam table: its points need more than its max-accel even at 1 lathe rpm",
        }
    }
}

impl core::fmt::Display for MotionError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            MotionError::Rate { span: 1, apart, needs_hz, max_hz } => write!(
                f,
                "cam table: neighbouring points {apart} steps apart need {needs_hz} X steps/s at {SLOWEST_RPM} lathe rpm, beyond its max-rate {max_hz} steps/s"
            )?,
            MotionError::Rate { span, apart, needs_hz, max_hz } => write!(
                f,
                "cam table: points {span} apart move {apart} steps, which needs {needs_hz} X steps/s at {SLOWEST_RPM} lathe rpm, beyond its max-rate {max_hz} steps/s"
            )?,
            MotionError::Accel { span: 1, bend, needs, max } => write!(
                f,
                "cam table: a bend of {bend} steps at a point needs {needs} X steps/s^2 at {SLOWEST_RPM} lathe rpm, beyond its max-accel {max} steps/s^2"
            )?,
            MotionError::Accel { span, bend, needs, max } => write!(
                f,
                "cam table: a bend of {bend} steps over points {span} apart needs {needs} X steps/s^2 at {SLOWEST_RPM} lathe rpm, beyond its max-accel {max} steps/s^2"
            )?,
        }
        write!(f, " (a table must be followed at {SLOWEST_RPM} rpm or faster)")
    }
}

/// The largest difference between points `k` apart and the largest
/// second difference at spacing `k`, around the period (the table wraps),
/// in steps.
fn steepest(points: &[i32], k: usize) -> (u64, u64) {
    let n = points.len();
    let at = |i: usize| points.get(i % n.max(1)).copied().unwrap_or(0) as i64;
    (0..n).fold((0, 0), |(d1, d2), i| {
        let (a, b, c) = (at(i), at(i + k), at(i + 2 * k));
        (d1.max((b - a).unsigned_abs()), d2.max((c - 2 * b + a).unsigned_abs()))
    })
}

/// The spans the motion is measured over: 1, 2, 4 … segments, while two
/// spans fit in the period (the neighbours always).
fn spans(n: usize) -> impl Iterator<Item = usize> {
    core::iter::successors(Some(1usize), |k| k.checked_mul(2)).take_while(move |&k| 2 * k <= n.max(2))
}

/// The most a span of the table needs: (steps/s, span, apart) and
/// (steps/s², span, bend), at [`SLOWEST_RPM`].
type Need = (u64, u32, u32);

/// Checks the table against the X axis its header declares, at
/// [`SLOWEST_RPM`] on its encoder. A pass over the points per span (low
/// priority: 128-bit products, never in the tick).
///
/// A segment is `period / N` counts; at ω counts/s it lasts
/// `period / (N ω)` s, with ω = rpm · cpr / 60. A difference d over k
/// segments is then at least a speed (d − 1) · N ω / (k · period), and a
/// bend b at spacing k an acceleration (b − 2) · (N ω / (k · period))².
pub fn check(h: &CamHeader, points: &[i32]) -> Result<(), MotionError> {
    let (rate, accel) = needs(h, points);
    if rate.0 > h.max_rate_hz as u64 {
        return Err(MotionError::Rate { span: rate.1, apart: rate.2, needs_hz: rate.0, max_hz: h.max_rate_hz });
    }
    if accel.0 > h.max_accel as u64 {
        return Err(MotionError::Accel { span: accel.1, bend: accel.2, needs: accel.0, max: h.max_accel });
    }
    Ok(())
}

/// The largest speed and acceleration any span of the table needs.
fn needs(h: &CamHeader, points: &[i32]) -> (Need, Need) {
    // segments per minute at the slowest speed, and the seconds in a minute
    // per period: a segment is 60 · period / (N · cpr · rpm) s
    let per_min = points.len() as u128 * h.counts_per_rev as u128 * SLOWEST_RPM as u128;
    let period_s = 60 * h.period_counts.max(1) as u128;
    let (mut rate, mut accel) = ((0, 1, 0), (0, 1, 0));
    for k in spans(points.len()) {
        let (d1, d2) = steepest(points, k);
        let span_s = period_s * k as u128;
        let hz = ceil_div(d1.saturating_sub(1) as u128 * per_min, span_s);
        let acc = ceil_div(d2.saturating_sub(2) as u128 * per_min * per_min, span_s * span_s);
        if hz > rate.0 {
            rate = (hz, clamp(k as u64), clamp(d1));
        }
        if acc > accel.0 {
            accel = (acc, clamp(k as u64), clamp(d2));
        }
    }
    (rate, accel)
}

/// ⌈num / den⌉ (`den` > 0), saturating at `u64::MAX`; out of line, so the
/// firmware holds one copy of the 128-bit division.
/// (`div_ceil` takes a remainder too: 188 bytes more of the image.)
#[inline(never)]
#[allow(clippy::manual_div_ceil)]
fn ceil_div(num: u128, den: u128) -> u64 {
    // num < 2^118 (a step < 2^34, N · cpr < 2^42): no overflow; den <
    // 2^(2·(38 + 10)) (60 · period < 2^38, k < 2^10)
    ((num + den - 1) / den).min(u64::MAX as u128) as u64
}

fn clamp(v: u64) -> u32 {
    v.min(u32::MAX as u64) as u32
}
