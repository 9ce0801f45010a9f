//! Once a second over defmt: lathe and cutter rpm, phase error, tick cost.

use super::tick;
use defmt::info;
use embassy_time::Timer;

#[embassy_executor::task]
pub async fn every_second() {
    let mut checked = false;
    loop {
        Timer::after_millis(1000).await;
        // again once everything is up (USB, the self-test's timer and the
        // planning executor enable their interrupts after boot's check)
        if !core::mem::replace(&mut checked, true) && !super::priorities::check() {
            defmt::error!("an interrupt reaches the tick's level: fix board::PRIORITIES");
        }
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
