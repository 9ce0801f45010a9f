//! The steps' spacing at a steady lathe, fed what a real encoder gives:
//! whole counts read at the interrupt's latency, and A's rises latched to
//! the µs (`hwsim::latches`), through the whole controller and the RM0383
//! model of the step output. The goal: within 1 % of the period from
//! 1 kHz to 240 kHz (the top speed a 250 kHz `max-rate` leaves a lathe),
//! and no reversal of DIR at a steady speed.

use polyturn_bench::hwsim::steady_lathe::steady_lathe;
use polyturn_bench::hwsim::Isr;
use polyturn_stm32_model::Params;

#[test]
fn a_steady_lathe_spaces_the_steps_within_one_percent_and_never_reverses() {
    for hz in [1_000.0, 10_000.0, 64_000.0, 123_457.0, 240_000.0] {
        let (o, spacing) = steady_lathe(hz, Isr::new((200, 2_000)), Params::default());
        assert!(o.faults.is_empty(), "{hz}: {:?}", o.faults);
        assert!(spacing.steps >= 200, "{hz}: {} steps judged", spacing.steps);
        // 1 %, and the timer's whole cycle (a period of 400 cycles at 240 kHz)
        let cycle = 1.0 / (96e6 / hz);
        assert!(spacing.worst_fraction <= 0.01 + cycle, "{hz}: {:.4}", spacing.worst_fraction);
        assert_eq!(o.received.reversals, 0, "{hz}");
    }
}
