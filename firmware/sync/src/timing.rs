//! The control tick's rate and the step timer's clock: a leaf, so that the
//! settings' checks (`config::bldc_out`) and everything derived from the
//! settings (`derived`) can both take it.

/// The control tick's rate and the step timer's clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    pub tick_hz: u32,
    pub step_timer_hz: u32,
}

impl Timing {
    /// The board's: 20 kHz tick, 96 MHz timer clock. The firmware's clock
    /// tree (`polyturn_firmware::clocks`) fails to build unless it makes
    /// exactly this; the simulator, the fake board and the page use it.
    pub const FIRMWARE: Timing = Timing { tick_hz: 20_000, step_timer_hz: 96_000_000 };
}
