//! The LED and the watchdog, every 25 ms, on the main executor.

use super::{keys, priorities, tick};
use defmt::info;
use embassy_stm32::gpio::{Level, Output};
use embassy_stm32::peripherals::IWDG;
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_time::Timer;

/// Pets the watchdog while the tick runs and shows the state on the LEDs
/// (PC13, active low; PA10, active high).
#[embassy_executor::task]
pub async fn run(mut dog: IndependentWatchdog<'static, IWDG>, mut led: Output<'static>, mut ext_led: Output<'static>) {
    let mut loops = 0u32;
    loop {
        // The watchdog is fed only while the tick runs: a hung tick resets
        // the MCU, and reset leaves every output inactive.
        let alive = tick::alive();
        if alive {
            dog.pet();
        }
        let state = tick::with_core(|c| c.state()).unwrap_or(polyturn_sync::State::Idle);
        let ms = embassy_time::Instant::now().as_millis() as u32;
        let lit = polyturn_firmware::led::lit(state, alive, ms, keys::refused_at());
        led.set_level(if lit { Level::Low } else { Level::High });
        ext_led.set_level(if lit { Level::High } else { Level::Low });
        if loops == 4 {
            // 100 ms in: every driver has enabled its interrupts
            if priorities::check() {
                info!("interrupt priorities as in board::PRIORITIES");
            }
        }
        loops = loops.saturating_add(1);
        Timer::after_millis(25).await;
    }
}
