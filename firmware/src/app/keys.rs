//! The keys at the lathe (`polyturn_firmware::keys`): sampled every
//! millisecond in the planning executor, far below the tick; each action
//! holds the tick's lock only for the controller call.

use super::tick;
use core::sync::atomic::{AtomicU32, Ordering};
use embassy_stm32::gpio::{Input, Pull};
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;
use polyturn_firmware::keys::{nudged_phase, Events, Keys};
use polyturn_sync::controller::PreparedConfig;

/// When (ms since boot, +1; 0 = never) a key press was last refused: the
/// LED flickers (`led::lit`).
static REFUSED_AT: AtomicU32 = AtomicU32::new(0);

pub fn refused_at() -> Option<u32> {
    match REFUSED_AT.load(Ordering::Relaxed) {
        0 => None,
        t => Some(t - 1),
    }
}

fn refuse(ms: u32) {
    REFUSED_AT.store(ms.wrapping_add(1).max(1), Ordering::Relaxed);
}

pub struct KeyPins {
    pub engage: Peri<'static, P::PB12>,
    pub stop: Peri<'static, P::PB10>,
    pub plus: Peri<'static, P::PB9>,
    pub minus: Peri<'static, P::PA15>,
}

#[embassy_executor::task]
pub async fn read(pins: KeyPins) {
    // switches to GND with the pins' pull-ups: pressed reads low
    let inputs = [
        Input::new(pins.engage, Pull::Up),
        Input::new(pins.stop, Pull::Up),
        Input::new(pins.plus, Pull::Up),
        Input::new(pins.minus, Pull::Up),
    ];
    let mut keys = Keys::default();
    loop {
        let ms = embassy_time::Instant::now().as_millis() as u32;
        let pressed = [0, 1, 2, 3].map(|i| inputs[i].is_low());
        act(keys.sample(ms, pressed), ms);
        embassy_time::Timer::after_millis(1).await;
    }
}

fn act(e: Events, ms: u32) {
    if e.stop {
        // STOP first, and alone: a press of both stops
        tick::with_core(|c| c.disengage());
        return;
    }
    if e.engage && !matches!(tick::with_core(|c| c.engage()), Some(Ok(()))) {
        refuse(ms);
    }
    if e.phase != 0 && !nudge(e.phase) {
        refuse(ms);
    }
}

/// A phase nudge: the settings derived outside the lock, installed under
/// it if nothing changed them meanwhile.
fn nudge(dir: i8) -> bool {
    let Some((c, generation)) = tick::with_core(|c| (*c.config(), c.config_generation())) else { return false };
    let Some(phase) = nudged_phase(c.phase_offset_mdeg, dir) else { return false };
    let next = polyturn_sync::Config { phase_offset_mdeg: phase, ..c };
    let p = PreparedConfig::prepare(next, &c, tick::TIMING);
    let done = tick::with_core(|c| c.config_generation() == generation && c.install_config(&p).is_ok());
    done == Some(true)
}
