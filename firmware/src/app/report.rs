//! Once a second over defmt: lathe and cutter rpm, phase error, tick cost.

use super::tick;
use defmt::info;
use embassy_time::Timer;

#[embassy_executor::task]
pub async fn every_second() {
    loop {
        Timer::after_millis(1000).await;
        let (ticks, avg, worst) = tick::take_cost();
        // defmt-rtt holds the critical section for a whole line (80 µs,
        // `cs.rs`), which would hold off the self-test's TIM9 interrupt
        // past its index deadline (`quadgen`): no report while it runs
        if super::selftest::playing() {
            continue;
        }
        // Copy under the lock, format outside it (the tick shares the lock).
        if let Some(snap) = tick::with_core(|c| polyturn_sync::console::Snapshot::of(c)) {
            let mut line = polyturn_sync::console::Reply::new();
            snap.write(&mut line);
            let late = tick::steps_late();
            info!(
                "{} | tick {} cycles avg, {} worst ({} ticks), step segments late {}, NDTR lead {}",
                line.as_str(),
                avg,
                worst,
                ticks,
                late,
                tick::ndtr_lead()
            );
        }
    }
}
