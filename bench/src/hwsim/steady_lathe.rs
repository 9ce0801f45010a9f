//! A lathe at a steady speed through the whole controller, its encoder's
//! edges latched as the board latches them (`edges`): the step spacing a
//! real encoder gives, against the ideal train of the exact gear.

use super::scenarios::{lathe, Outcome};
use super::{Isr, TIMER_HZ};
use polyturn_stm32_model::Params;
use polyturn_sync::Config;

/// Steps/s at 2:1 on 3200 steps and 2400 counts: 8/3 steps a count.
const STEPS_PER_COUNT: f64 = 2.0 * 3200.0 / 2400.0;

/// The lathe brought up to `hz` steps/s and held there, engaged from rest
/// (`max-accel` 5 000 000 steps/s²); the steps judged 50 ms after the
/// lathe reached its speed.
pub fn steady_lathe(hz: f64, isr: Isr, params: Params) -> (Outcome, SteadySpacing) {
    let counts_per_s = hz / STEPS_PER_COUNT;
    let rpm = counts_per_s / 2400.0 * 60.0;
    let config = Config::default()
        .with("max-rate", "250000")
        .and_then(|c| c.with("max-accel", "5000000"))
        .and_then(|c| c.with("max-rpm", &format!("{}", (rpm.ceil() as u32 + 1).max(1))))
        .and_then(|c| c.with("ratio", "2"))
        .unwrap_or_default();
    // up to speed at 2 500 000 steps/s² (half the cutter's limit), then
    // long enough for 400 judged steps, or 0.2 s of them
    let ramp_s = hz / 2.5e6;
    let settle_s = ramp_s + 0.05;
    let seconds = settle_s + (400.0 / hz).clamp(0.02, 0.2);
    let x = super::scenarios::ramp(2400.0, rpm, ramp_s, seconds);
    let o = lathe(config, &x, seconds, isr, params, None);
    let from = (settle_s * TIMER_HZ as f64) as u64;
    let spacing = SteadySpacing::of(&o.received.rises, from, TIMER_HZ as f64 / hz);
    (o, spacing)
}

/// The spacing of the steps after `from` (cycles) against the ideal
/// period: the worst |interval − period|, as a fraction of the period.
#[derive(Clone, Copy, Debug, Default)]
pub struct SteadySpacing {
    pub worst_fraction: f64,
    pub steps: usize,
}

impl SteadySpacing {
    fn of(rises: &[u64], from: u64, period: f64) -> SteadySpacing {
        let judged: Vec<u64> = rises.iter().copied().filter(|&r| r >= from).collect();
        let worst = judged.windows(2).map(|w| ((w[1] - w[0]) as f64 - period).abs() / period).fold(0.0, f64::max);
        SteadySpacing { worst_fraction: worst, steps: judged.len() }
    }
}
