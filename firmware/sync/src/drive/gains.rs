//! The phase loop's gains, from the drive's update rate and time constant
//! (issue 30, item 2), worked out at low priority (`Derived`).
//!
//! From the speed command to the cutter's angle the drive is a delay and a
//! lag: the command is taken once per frame and held (a zero-order hold:
//! on average half a frame late, plus the tick), and the speed follows it
//! with the drive's time constant τ (`bldc-tau`: a spindle driver's speed
//! loop, or an RC ESC's motor, which has none). Two loops close around it:
//!
//! * **Speed feedback** Kv on the error's rate (the speed error, filtered
//!   over about the delay, 2^shift ticks, so a count's step is spread):
//!   Kv / (1 + sτ) crosses over at Kv/τ, where the delay and the filter
//!   cost Kv·T/τ ≤ ½ rad, so Kv = τ / 2T, at most 32 (a count's step
//!   times Kv must not swamp the command). It makes the drive τ/(1 + Kv)
//!   slow; an ESC's sag under load shrinks by as much.
//! * **Phase PI** around that, crossing over at ω_c = 1 / (2 (τ' + T)):
//!   the lag costs at most atan(½) ≈ 27°, the delay ½ rad, the integral's
//!   corner at ω_c / 4 another 14°. A drive slower than its setting gets
//!   less margin, so the default (20 ms) errs slow.
//!
//! In tick units: Kp = ω_c / f_tick, the integral gain Kp·ω_c/4/f_tick =
//! Kp²/4, and the acceleration feed-forward τ·f_tick ticks (a drive lagging
//! τ behind its command is ahead of it by τ·a if asked τ·a more).

use crate::config::Config;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BldcGains {
    /// proportional: Q16 speed (counts per tick) per Q16 count of error,
    /// ×2^16
    pub kp_q16: i64,
    /// integral: per tick, ×2^32
    pub ki_q32: i64,
    /// τ in ticks: the feed-forward of the follower's acceleration
    pub tau_ticks: i64,
    /// the error's rate (the speed error) fed back, ×2^8
    pub kv_q8: i64,
    /// the rate's filter: 2^-shift of each tick's change
    pub rate_shift: u32,
}

/// Kv's ceiling, ×2^8.
const KV_MAX_Q8: u64 = 32 << 8;

impl BldcGains {
    pub fn new(c: &Config, tick_hz: u32) -> BldcGains {
        let tick_hz = tick_hz.max(1) as u64;
        let frame_hz = c.bldc_out.frame_hz(c.pwm_hz).max(1) as u64;
        let tau_ticks = c.bldc_tau_ms as u64 * tick_hz / 1_000;
        // T: half a frame (the hold) and the tick, in ticks, rounded up,
        // and the rate's filter (a power of two, about as long)
        let hold = tick_hz.div_ceil(2 * frame_hz) + 1;
        let rate_shift = (u64::BITS - 1 - hold.leading_zeros()).min(10);
        let delay = hold + (1 << rate_shift);
        let kv_q8 = ((tau_ticks << 8) / (2 * delay)).min(KV_MAX_Q8);
        let tau_eff = (tau_ticks << 8) / (256 + kv_q8);
        let kp_q16 = (1u64 << 15) / (tau_eff + delay).max(1);
        BldcGains {
            kp_q16: kp_q16 as i64,
            ki_q32: (kp_q16 * kp_q16 / 4) as i64,
            tau_ticks: tau_ticks as i64,
            kv_q8: kv_q8 as i64,
            rate_shift,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gains(out: &str, tau_ms: &str) -> BldcGains {
        let c = Config::default().with("bldc-out", out).unwrap().with("bldc-tau", tau_ms).unwrap();
        BldcGains::new(&c, 25_000)
    }

    #[test]
    fn a_spindle_driver_at_1_khz_with_2_ms() {
        // τ 50 ticks; the hold 13 + 1, the filter 8: T = 22; Kv = 50 / 44
        // (290 / 256); τ' = 12 800 / 546 = 23; Kp = 32 768 / 45 = 728:
        // ω_c = 278 rad/s
        let g = gains("pwm", "2");
        assert_eq!(g, BldcGains { kp_q16: 728, ki_q32: 132_496, tau_ticks: 50, kv_q8: 290, rate_shift: 3 });
    }

    #[test]
    fn an_esc_at_400_hz_on_a_79_ms_motor_gets_strong_speed_feedback() {
        // τ 1 975; T = 33 + 32; Kv = 1 975 / 130 = 15.2; τ' = 121
        let g = gains("esc400", "79");
        assert_eq!((g.kv_q8, g.rate_shift, g.kp_q16), (3_889, 5, 32_768 / (121 + 65)));
    }

    #[test]
    fn a_slower_frame_or_drive_gets_a_softer_loop() {
        let esc50 = gains("esc50", "20");
        let esc400 = gains("esc400", "20");
        let pwm = gains("pwm", "20");
        assert!(esc50.kp_q16 < esc400.kp_q16 && esc400.kp_q16 < pwm.kp_q16);
        assert!(gains("pwm", "100").kp_q16 < pwm.kp_q16);
        assert_eq!(gains("oneshot125", "1000").tau_ticks, 25_000);
        assert_eq!(gains("oneshot125", "1000").kv_q8, 32 << 8, "Kv at its ceiling");
    }

    #[test]
    fn the_products_in_the_tick_fit_64_bits() {
        // the stiffest the settings allow: τ 1 ms, PWM at 20 kHz
        let c = Config::default().with("bldc-out", "pwm").unwrap().with("pwm-hz", "20000").unwrap();
        let g = BldcGains::new(&c.with("bldc-tau", "1").unwrap(), 25_000);
        // the error is bounded to 2^36 (`drive::ERROR_BOUND`), its rate to
        // 2^37
        assert!((g.kp_q16 as i128) << 36 < i64::MAX as i128 >> 2);
        assert!((g.ki_q32 as i128) << 36 < i64::MAX as i128 >> 2);
        assert!((KV_MAX_Q8 as i128) << 37 < i64::MAX as i128 >> 2);
    }
}
