//! One source of timed boundaries: where the lathe last crossed one (in
//! half counts), when (Q8 stamps), and the speed and acceleration from
//! the crossings before. The position at an instant is the crossing's
//! place plus the travel since, stopping where a slowing lathe stops.

/// Timed crossings further apart than this many stamps give no speed: the
/// 16-bit stamp wraps at 65 536 µs.
const MAX_INTERVAL_STAMPS: i32 = 60_000;
/// Half counts between two crossings beyond which no speed is taken:
/// keeps the division's numerator (span · stamps a tick · 2^15) in 31 bits.
const MAX_SPAN_HALF: i64 = 512;
/// A track whose acceleration comes this late (`accel_min` at least this)
/// uses the mean speed alone until it comes: the count's changes, the only
/// news of a lathe starting from rest.
pub(super) const LATE_ACCEL: i32 = 1_000;

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Track {
    /// the last crossing's place, half counts
    half: Option<i64>,
    stamp_q8: u32,
    /// Q16 ticks from the last crossing to this tick's instant (saturating)
    age_q16: i32,
    /// stamps between the last two crossings
    interval: i32,
    /// Q16 ticks: half that interval (worked out once a crossing, not
    /// every tick)
    half_interval_q16: i64,
    /// Q16 counts a tick between the last two crossings, once usable
    velocity_q16: Option<i64>,
    /// the same, measured whether or not usable (the next acceleration's)
    last_speed: Option<i64>,
    /// Q22 counts a tick² (a starting lathe's 48 000 counts/s² is 5 in
    /// Q16: too coarse)
    accel_q22: i64,
    /// the furthest travel since the last crossing (a slowing lathe's stop)
    peak_q16: Option<i64>,
}

/// The acceleration between two mean speeds (Q16 counts a tick) taken
/// over intervals summing `stamps`: Δv over the time between the
/// intervals' middles. Slow crossings only (≤ 2 counts a tick), so the
/// numerator Δv·2·per_tick·2^6 stays in 31 bits: a 32-bit division.
fn accel_q22(dv_q16: i64, per_tick: i32, stamps: i32) -> i64 {
    let dv = dv_q16.clamp(-(1 << 17), 1 << 17) as i32;
    (((dv * 2 * per_tick.min(255)) << 6) / stamps.max(1)) as i64
}

/// What a crossing is judged by: this tick's instant, the stamps a tick
/// and their inverse, and the interval from which the acceleration counts.
#[derive(Clone, Copy, Debug)]
pub(super) struct Clock {
    pub instant_q8: u32,
    pub per_tick: i32,
    /// (at most 2^16: 32 bits, so each product with it is one SMULL)
    pub ticks_per_stamp_q16: i32,
    pub accel_min: i32,
    /// crossings closer than this many stamps give no speed: their times'
    /// error is too large a share of the interval
    pub interval_min: i32,
}

impl Track {
    /// A tick with no new crossing.
    #[inline]
    pub fn age(&mut self) {
        self.age_q16 = self.age_q16.saturating_add(1 << 16);
    }

    /// A new crossing at `half` at `stamp_q8`, seen at `instant_q8`. Its
    /// speed needs the one before; from slow crossings (`accel_min`
    /// stamps or more apart) it takes the acceleration too, and needs it:
    /// the last interval's mean speed lags a starting lathe by a·T/2.
    /// (Inlined where the compiler will: kept out of line, a tick with a
    /// new rise cost 18 instructions more, though the average tick 3
    /// fewer; `#[inline(always)]` cost both more: counted on an emulated Cortex-M4.)
    #[inline]
    pub fn observe(&mut self, half: i64, stamp_q8: u32, clock: Clock) {
        let since = clock.instant_q8.wrapping_sub(stamp_q8) & super::WRAP_Q8;
        let age_q8 = ((since << 8) as i32) >> 8;
        // (as of the last tick: a tick more or less is nothing to the limit)
        let prev_age_q16 = self.age_q16 as i64;
        let old_speed = self.last_speed.take();
        let old_interval = self.interval;
        (self.velocity_q16, self.accel_q22) = (None, 0);
        let fresh = prev_age_q16 < MAX_INTERVAL_STAMPS as i64 * clock.ticks_per_stamp_q16 as i64;
        if let Some(prev) = self.half.filter(|_| fresh) {
            let interval = ((stamp_q8.wrapping_sub(self.stamp_q8) & super::WRAP_Q8) >> 8) as i32;
            let span = half - prev;
            let per_tick = clock.per_tick;
            let usable = interval >= clock.interval_min && span.abs() <= MAX_SPAN_HALF;
            // only then the division: a span within the limit and at most 64
            // stamps a tick keep its numerator in 31 bits (`checked_div`:
            // no panic path on the tick, though `interval_min` ≥ 1 keeps 0 out)
            let speed = usable.then(|| (((span as i32) * per_tick) << 15).checked_div(interval));
            if let Some(Some(v)) = speed {
                let v = v as i64;
                self.interval = interval;
                self.half_interval_q16 = (interval as i64 * clock.ticks_per_stamp_q16 as i64) >> 1;
                self.last_speed = Some(v);
                let slow = interval >= clock.accel_min;
                match old_speed {
                    // either interval slow: a lathe slowing through the
                    // limit keeps its measurement
                    Some(v1) if slow || old_interval >= clock.accel_min => {
                        // (none at a standstill between two rises at one
                        // place: `accelerated` takes its sense from v)
                        if v != 0 {
                            self.accel_q22 = accel_q22(v - v1, per_tick, interval + old_interval);
                        }
                        self.velocity_q16 = Some(v);
                    }
                    _ if slow && clock.accel_min < LATE_ACCEL => {}
                    _ => self.velocity_q16 = Some(v),
                }
            }
        }
        let age_q16 = ((age_q8 as i64 * clock.ticks_per_stamp_q16 as i64) >> 8) as i32;
        (self.half, self.stamp_q8, self.age_q16, self.peak_q16) = (Some(half), stamp_q8, age_q16, None);
    }

    /// The position now, Q16 counts; none without a usable speed. A lathe
    /// that stops between crossings is run on only to its count's edge
    /// (`EdgeTimer::measure` bounds it there), and a slowing one stops
    /// where its speed reaches 0 (`accelerated`): neither runs away, and
    /// neither turns the cutter back.
    #[inline]
    pub fn position_q16(&mut self) -> Option<i64> {
        let half = self.half?;
        let velocity = self.velocity_q16?;
        Some((half << 15) + self.travel_q16(velocity, self.age_q16 as i64))
    }

    /// Q16 counts travelled in `age` (Q16 ticks): the interval's mean
    /// speed, plus the acceleration from that mean at the interval's
    /// middle (a·(T/2·age + age²/2)), never past a stop.
    #[inline]
    fn travel_q16(&mut self, velocity: i64, age_q16: i64) -> i64 {
        let plain = (velocity * age_q16) >> 16;
        if self.accel_q22 == 0 {
            return plain;
        }
        self.accelerated(plain, velocity, age_q16)
    }

    /// The acceleration's part (slow crossings only: out of the common
    /// path, whose registers it would otherwise crowd).
    #[inline(never)]
    fn accelerated(&mut self, plain: i64, velocity: i64, age_q16: i64) -> i64 {
        let age = age_q16.min(1 << 27);
        let time_q16 = ((self.half_interval_q16 * age) >> 16) + ((age * age) >> 17);
        let travel = plain + ((self.accel_q22 * time_q16) >> 22);
        // slowing: the lathe stops where its speed reaches 0, and stays
        // (the travel turning back against the speed's sign)
        let peak = match self.peak_q16 {
            Some(p) if (travel - p).signum() * velocity.signum() < 0 => p,
            _ => travel,
        };
        self.peak_q16 = Some(peak);
        peak
    }
}
