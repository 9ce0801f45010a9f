//! The self-test's speed profile: rest, ramp up, hold, ramp down, rest,
//! the same backwards, rest. The lathe stands still at every rest, so
//! what the gearbox did can be compared with the books exactly there.

/// What a leg does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Rest,
    Ramp,
    Hold,
}

/// One leg of the profile: `from_rpm` to `to_rpm` (signed: negative turns
/// backward) over `ms`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leg {
    pub kind: Kind,
    pub from_rpm: i32,
    pub to_rpm: i32,
    pub ms: u32,
}

/// Legs in a profile.
pub const LEGS: usize = 9;
/// The first rest: long enough for the engagement at rest to reach the
/// phase (at most half a cutter turn, `Controller::engage`).
pub const FIRST_REST_MS: u32 = 2_000;
pub const REST_MS: u32 = 600;
pub const HOLD_MS: u32 = 2_000;
/// Shortest ramp; longer when the cutter would need more than half its
/// `max-accel` (`ramp_ms`).
pub const MIN_RAMP_MS: u32 = 1_000;
/// A rest's figures are read this long before it ends: the lathe has
/// stood still for `REST_MS - SETTLE_BEFORE_END_MS` and the cutter with it.
pub const SETTLE_BEFORE_END_MS: u32 = 100;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plan {
    pub rpm: u32,
    pub cpr: u32,
    pub legs: [Leg; LEGS],
}

impl Plan {
    pub fn new(rpm: u32, cpr: u32, ramp_ms: u32) -> Plan {
        let r = rpm as i32;
        let rest = |ms| Leg { kind: Kind::Rest, from_rpm: 0, to_rpm: 0, ms };
        let ramp = |from_rpm, to_rpm| Leg { kind: Kind::Ramp, from_rpm, to_rpm, ms: ramp_ms };
        let hold = |rpm| Leg { kind: Kind::Hold, from_rpm: rpm, to_rpm: rpm, ms: HOLD_MS };
        let legs = [
            rest(FIRST_REST_MS),
            ramp(0, r),
            hold(r),
            ramp(r, 0),
            rest(REST_MS),
            ramp(0, -r),
            hold(-r),
            ramp(-r, 0),
            rest(REST_MS),
        ];
        Plan { rpm, cpr, legs }
    }

    pub fn total_ms(&self) -> u32 {
        self.legs.iter().map(|l| l.ms).sum()
    }

    /// The leg `ms` into the profile (the last one past its end).
    pub fn leg_at(&self, ms: u32) -> usize {
        let mut end = 0;
        for (i, l) in self.legs.iter().enumerate() {
            end += l.ms;
            if ms < end {
                return i;
            }
        }
        LEGS - 1
    }

    /// When leg `i` ends, ms into the profile.
    pub fn end_of(&self, i: usize) -> u32 {
        self.legs.iter().take(i + 1).map(|l| l.ms).sum()
    }
}

/// A ramp's length: `MIN_RAMP_MS`, or longer so the cutter accelerates at
/// no more than half `max_accel` (steps/s²) to `rate_hz` (its steps/s at
/// the hold): the follower keeps up without a following error.
pub fn ramp_ms(rate_hz: u64, max_accel: u32) -> u32 {
    let ms = (2_000 * rate_hz).div_ceil(max_accel.max(1) as u64);
    ms.clamp(MIN_RAMP_MS as u64, 60_000) as u32
}

/// Motor steps per second at `rpm` of the lathe: rpm × cpr / 60 × num/den.
pub fn rate_hz(rpm: u32, cpr: u32, num: u64, den: u64) -> u64 {
    (rpm as u128 * cpr as u128 * num as u128 / (60 * den.max(1) as u128)) as u64
}
