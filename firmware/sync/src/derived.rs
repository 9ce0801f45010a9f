//! Everything the tick needs, precomputed from a `Config` at low priority
//! (this is where the divisions live, so the tick has none of 64 bits).

use crate::config::{Config, Sense};
use crate::follower::Limits;
use crate::gear::Scale;
use crate::steps::StepTiming;
use crate::timing::Timing;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Derived {
    pub scale: Scale,
    pub sense_positive: bool,
    /// motor steps per lathe count, Q16
    pub steps_per_count_q16: i64,
    /// 2^(15 + REM_FRAC) / den: see `remainder_q16`
    pub rem_inv: i64,
    pub max_counts_per_tick: i32,
    pub limits: Limits,
    pub following_limit_q16: i64,
    pub phase_offset_q16: i64,
    pub steps: StepTiming,
    pub still_ticks: u32,
    pub stall_ticks: u32,
    pub tick_hz: u32,
    /// the BLDC phase loop's gains (`drive::gains`)
    pub bldc: crate::drive::gains::BldcGains,
    /// ticks from the encoder reading to the end of the window the tick's
    /// output fills (`Controller::ahead`)
    pub ahead_ticks: i64,
}

/// Shortest STEP pulse the board emits: a `pulse` setting below it is
/// stretched to it (drivers take longer pulses; the limit is the DMA's
/// reload time, see `polyturn_firmware::stepgen`).
pub const STEP_FLOOR_NS: u32 = 1_000;

/// The gear's remainder in Q16 steps is rem2 / (2·den) · 2^16, that is
/// rem2 · 2^15 / den. `rem_inv` holds 2^15 / den with `REM_FRAC` more
/// fraction bits, so a den past 2^15 keeps its precision and the tick
/// multiplies and shifts (|rem2| ≤ den: the product is at most 2^39).
const REM_FRAC: u32 = 24;

fn ceil_div(a: u64, b: u64) -> u64 {
    a.div_ceil(b.max(1))
}

/// Ticks from the encoder reading to the end of the window that a tick's
/// output fills: one, plus the step output's pipeline. A BLDC's loop
/// compares the target with its encoder, read at the tick's instant as the
/// lathe's is: the target there, not a tick ahead (a tick ahead, its
/// integral would hold the cutter a tick early: 2.6 counts at 1 200 rpm
/// of a 3 200-count encoder).
fn ahead_ticks(drive: crate::config::DriveKind) -> i64 {
    use crate::config::DriveKind;
    match drive {
        DriveKind::Stepper => 1 + crate::steps::pipe::LEAD_TICKS,
        DriveKind::Bldc => 0,
        DriveKind::None => 1,
    }
}

impl Derived {
    pub fn new(c: &Config, t: Timing) -> Derived {
        let scale = Scale::new(c.ratio.num(), c.ratio.den(), c.motor_steps_per_rev, c.encoder_counts_per_rev)
            .unwrap_or(Scale { num: 1, den: 1 });
        let hz = t.tick_hz.max(1) as u64;
        // Top lathe speed in counts per tick, with 25 % margin and 2 counts
        // of jitter allowance; a tick can never move half the 16-bit range.
        let counts = ceil_div(c.max_lathe_rpm as u64 * c.encoder_counts_per_rev as u64 * 5, 60 * hz * 4) + 2;
        let ns_to_timer = |ns: u32| ceil_div(ns as u64 * t.step_timer_hz as u64, 1_000_000_000) as u32;
        // The step timer takes its next segment by DMA at each update: no
        // segment may be shorter than the DMA needs (`STEP_FLOOR_NS`), and
        // every pulse is a segment's high part.
        let pulse = ns_to_timer(c.step_pulse_ns.max(STEP_FLOOR_NS));
        Derived {
            scale,
            sense_positive: c.sense == Sense::Same,
            steps_per_count_q16: ((scale.num << 16) / scale.den) as i64,
            rem_inv: ((1u64 << (15 + REM_FRAC)) / scale.den) as i64,
            max_counts_per_tick: counts.min(16_000) as i32,
            limits: Limits::from_rates(c.max_step_rate_hz as u64, c.max_accel_steps_per_s2 as u64, hz)
                .with_start(c.start_rate_hz as u64, hz),
            following_limit_q16: (c.following_error_limit_steps as i64) << 16,
            phase_offset_q16: ((c.phase_offset_mdeg as i64 * c.motor_steps_per_rev as i64) << 16) / 360_000,
            steps: StepTiming {
                tick_len: (t.step_timer_hz as u64 / hz) as u32,
                // high for `pulse`, then at least as long low
                min_period: 2 * pulse,
                dir_setup: ns_to_timer(c.dir_setup_ns),
                pulse,
            },
            still_ticks: (hz / 10) as u32,
            stall_ticks: (hz / 5) as u32,
            tick_hz: t.tick_hz,
            bldc: crate::drive::gains::BldcGains::new(c, t.tick_hz),
            ahead_ticks: ahead_ticks(c.drive),
        }
    }

    /// The gear's rounding remainder (`Gear::rem2`) in Q16 steps, within
    /// half a step.
    #[inline(always)]
    pub fn remainder_q16(&self, rem2: i64) -> i64 {
        (rem2 * self.rem_inv) >> REM_FRAC
    }
}
