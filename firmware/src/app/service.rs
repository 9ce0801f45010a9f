//! The service task: the controller's low-priority work, every ms.

use super::{selftest, tick};

/// Low-priority planning: work the tick must not do (re-basing the gear),
/// the watch on ticks that never ran, and the log of every change of state
/// (the tick does not log).
#[embassy_executor::task]
pub async fn service(mut bench: selftest::Bench) {
    let mut last = polyturn_sync::State::Idle;
    loop {
        bench.service();
        // a tick that never ran (`edgetime::watch`): logged, clock re-measured
        tick::check_ticks();
        if let Some(state) = tick::with_core(|c| {
            c.service();
            c.state()
        }) {
            // (no log while the self-test plays: `report`)
            if state != last && !selftest::playing() {
                match state {
                    polyturn_sync::State::Fault(f) => defmt::warn!("fault: {}: {}", f.name(), f.reason()),
                    s => defmt::info!("{}", s.name()),
                }
                last = state;
            }
        }
        embassy_time::Timer::after_millis(1).await;
    }
}
