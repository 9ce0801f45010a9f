//! The phase loop's gains, from the drive's update rate and time constant,
//! worked out at low priority (`Derived`).
//!
//! From the speed command to the cutter's angle the drive is a delay and a
//! lag: the command is taken once per frame and held (a zero-order hold:
//! on average half a frame late, plus the tick), and the speed follows it
//! with the drive's time constant τ (`bldc-tau`: a spindle driver's speed
//! loop, or an RC ESC's motor, which has none). Two loops close around it:
//!
//! * **Speed feedback** Kv on the error's rate (the speed error), filtered
//!   over 2^shift ticks: at least the largest power of two within a
//!   frame. The drive takes one command a frame, so the rate's noise
//!   (whole counts) faster than that would only alias into the command:
//!   averaged over half a frame, the spindle driver's error wanders ±2
//!   counts at 30–50 Hz (`tests/bldc_drives.rs`: the hexagon 3.4 counts
//!   while cutting, 1.9 with the frame's filter).
//!   Around the lag, Kv / (1 + sτ)
//!   crosses over near Kv/τ (for Kv well over 1), where the hold and the
//!   filter, T, cost Kv·T/τ rad: Kv = τ / 2T keeps that to ½ rad. Kv is
//!   at most 32, and one count's step through the filter (2^16 >> shift)
//!   times Kv at most an eighth of full speed: where it would be more the
//!   filter lengthens, which lowers Kv and the noise with it. The drive
//!   then answers in τ' = τ / (1 + Kv), and an ESC's sag under load
//!   shrinks as much.
//! * **Phase PI** around that. What passes the speed feedback is divided
//!   by 1 + Kv; Kp and Ki carry that back, so the phase loop crosses over
//!   at ω_c = 1 / (2 (τ' + T)): there the lag and the delay cost at most
//!   ω_c (τ' + T) = ½ rad (atan x ≤ x), the integral's corner at ω_c / 4
//!   another 14°, a margin over 45°. An RC ESC cannot brake, so an
//!   overshoot as the cutter synchronises cannot be taken back: a first
//!   version, whose target was a tick ahead of the encoder's reading, lost
//!   phase there at this crossover and kept ESCs at ω_c / (1 + Kv); with
//!   the target at the reading's instant the full crossover holds `esc400`
//!   to 9–14 counts while cutting, against 46–59 at the lower one
//!   (`tests/bldc_drives.rs`).
//!
//! In tick units: Kp = ω_c (1 + Kv) / f_tick, the integral gain
//! Kp × ω_c / 4 / f_tick, and the acceleration feed-forward τ·f_tick
//! ticks (a drive lagging τ behind its command is ahead of it by τ·a if
//! asked τ·a more). A drive slower than its setting gets less margin, so
//! the default (20 ms) errs slow.

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
        // and the rate's filter (a power of two, about a frame)
        let hold = tick_hz.div_ceil(2 * frame_hz) + 1;
        let max_q16 = ((c.max_step_rate_hz as u64) << 16).div_ceil(tick_hz);
        let (rate_shift, kv_q8) = speed_feedback(tau_ticks, hold, tick_hz / frame_hz, max_q16);
        let delay = hold + (1 << rate_shift);
        let tau_eff = (tau_ticks << 8) / (256 + kv_q8);
        // the speed feedback divides what passes it by 1 + Kv: Kp carries
        // that back, crossing over at ω_c, the integral's corner at ω_c / 4
        let base = (1u64 << 15) / (tau_eff + delay).max(1);
        let kp_q16 = base * (256 + kv_q8) / 256;
        let ki_q32 = kp_q16 * base / 4;
        BldcGains {
            kp_q16: kp_q16 as i64,
            ki_q32: ki_q32 as i64,
            tau_ticks: tau_ticks as i64,
            kv_q8: kv_q8 as i64,
            rate_shift,
        }
    }
}

/// The rate's filter (2^shift ticks: the largest power of two within a
/// `frame` of ticks, or longer) and Kv.
/// Kv = τ / 2T, T the hold and the filter; one count's step through the
/// filter, 2^16 >> shift, times Kv must stay within an eighth of full
/// speed (`max_q16`), so where it would not the filter lengthens, which
/// lowers Kv and the noise with it.
fn speed_feedback(tau_ticks: u64, hold: u64, frame: u64, max_q16: u64) -> (u32, u64) {
    let kv = |shift: u32| ((tau_ticks << 8) / (2 * (hold + (1 << shift)))).min(KV_MAX_Q8);
    let cap = |shift: u32| (max_q16 << shift) >> 11;
    let first = (u64::BITS - 1 - frame.max(1).leading_zeros()).min(10);
    let shift = (first..10).find(|&s| kv(s) <= cap(s)).unwrap_or(10);
    (shift, kv(shift).min(cap(shift)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::BldcOut;

    /// The board's tick: the figures below are worked out at 20 kHz.
    const TICK_HZ: u32 = crate::Timing::FIRMWARE.tick_hz;

    fn gains(out: &str, tau_ms: &str) -> BldcGains {
        assert_eq!(TICK_HZ, 20_000, "the figures are the board's");
        let c = Config::default().with("bldc-out", out).unwrap().with("bldc-tau", tau_ms).unwrap();
        BldcGains::new(&c, TICK_HZ)
    }

    #[test]
    fn a_spindle_driver_at_1_khz_with_2_ms() {
        // τ 40 ticks; the hold 10 + 1, the filter 16 (a frame is 20
        // ticks): T = 27; Kv = 40 / 54 (189 / 256); τ' = 10 240 / 445 =
        // 23; Kp = 32 768 / 50 = 655 (ω_c = 200 rad/s), × 445 / 256 for
        // the speed feedback = 1 138; Ki = 1 138 × 655 / 4 = 186 347 (the
        // corner at ω_c / 4)
        let g = gains("pwm", "2");
        assert_eq!(g, BldcGains { kp_q16: 1_138, ki_q32: 186_347, tau_ticks: 40, kv_q8: 189, rate_shift: 4 });
    }

    #[test]
    fn an_esc_at_400_hz_on_a_79_ms_motor_gets_strong_speed_feedback() {
        // τ 1 580; T = 26 + 32; Kv = 1 580 / 116 = 13.6; τ' = 108; ω_c =
        // 32 768 / 166 = 197 a 65 536th, × 3 742 / 256 = 2 879
        let g = gains("esc400", "79");
        assert_eq!((g.kv_q8, g.rate_shift, g.kp_q16), (3_486, 5, 197 * 3_742 / 256));
    }

    #[test]
    fn a_slower_frame_or_drive_gets_a_softer_loop() {
        let esc50 = gains("esc50", "20");
        let esc400 = gains("esc400", "20");
        let pwm = gains("pwm", "20");
        assert!(esc50.kp_q16 < esc400.kp_q16 && esc400.kp_q16 < pwm.kp_q16);
        // a slower spindle driver: more speed feedback (which then makes it
        // about as quick: the PI carries the 1 + Kv back)
        assert!(gains("pwm", "100").kv_q8 > pwm.kv_q8);
        assert_eq!(gains("oneshot125", "1000").tau_ticks, TICK_HZ as i64);
        // τ a second of ticks: Kv would be far past its ceiling of 32, and a
        // count's step through an 8-tick filter times 32 is 0.4 of full
        // speed (max-rate, 10 counts a tick): the filter lengthens to 32
        // ticks (0.1, within an eighth)
        let slow = gains("oneshot125", "1000");
        assert_eq!((slow.kv_q8, slow.rate_shift), (32 << 8, 5));
        let full_q16 = (200_000i64 << 16) / TICK_HZ as i64;
        assert!((((65_536 >> slow.rate_shift) * slow.kv_q8) >> 8) <= full_q16 / 8);
    }

    #[test]
    fn the_products_in_the_tick_fit_64_bits_for_every_setting() {
        // every interface, pwm-hz, bldc-tau and max-rate's extremes: the
        // error is bounded to 2^32 (`drive::ERROR_BOUND`), its rate to
        // 2^33; the integral to 1.5 × max-rate × 2^32 < 2^53
        let bound = super::super::ERROR_BOUND as i128;
        let hz = [1_000, 1_500, 2_000, 3_000, 4_000, 5_000, 8_000, 10_000, 12_500, 15_000, 16_000, 20_000];
        let (mut kp, mut ki) = (0, 0);
        for bldc_out in BldcOut::ALL {
            for pwm_hz in hz {
                for max_step_rate_hz in [1, 1_000, 200_000, 250_000] {
                    for bldc_tau_ms in 1..=1_000 {
                        let c = Config { bldc_out, pwm_hz, max_step_rate_hz, bldc_tau_ms, ..Config::default() };
                        let g = BldcGains::new(&c, TICK_HZ);
                        (kp, ki) = (kp.max(g.kp_q16), ki.max(g.ki_q32));
                        assert!(g.kv_q8 as u64 <= KV_MAX_Q8);
                    }
                }
            }
        }
        assert!(kp as i128 * bound < i64::MAX as i128 >> 2, "{kp}");
        assert!(ki as i128 * bound < i64::MAX as i128 >> 4, "{ki}");
        assert!(KV_MAX_Q8 as i128 * 2 * bound < i64::MAX as i128 >> 2);
    }
}
