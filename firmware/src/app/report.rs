//! Once a second over defmt: lathe and cutter rpm, phase error, tick cost.

use super::tick;
use defmt::info;
use embassy_time::Timer;

#[embassy_executor::task]
pub async fn every_second() {
    loop {
        Timer::after_millis(1000).await;
        let (ticks, avg, worst) = tick::take_cost();
        let line = tick::with_core(|c| {
            let mut out = polyturn_sync::console::Reply::new();
            polyturn_sync::console::status_line(c, &mut out);
            out
        });
        if let Some(line) = line {
            info!("{} | tick {} cycles avg, {} worst ({} ticks)", line.as_str(), avg, worst, ticks);
        }
    }
}
