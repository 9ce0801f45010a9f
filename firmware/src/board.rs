//! The Black Pill pin map, in one place (mirrored in the README wiring table).
//!
//! 5 V tolerant ("FT") pins are used for every input that comes from the
//! lathe side, which is often 5 V logic. PA6/PA7 (TIM3) and PB6/PB7 (TIM4)
//! are FT on the STM32F411 (datasheet DS10314, table 9).

/// One pin assignment: the signal, the MCU pin, and its role.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pin {
    pub signal: &'static str,
    pub pin: &'static str,
    pub function: &'static str,
    pub five_volt_tolerant: bool,
}

const fn pin(signal: &'static str, pin: &'static str, function: &'static str, ft: bool) -> Pin {
    Pin { signal, pin, function, five_volt_tolerant: ft }
}

/// The full pin map. `main.rs` takes the same pins by name.
pub const PINS: &[Pin] = &[
    pin("LATHE_A", "PA6", "TIM3_CH1, encoder mode, input filter", true),
    pin("LATHE_B", "PA7", "TIM3_CH2, encoder mode, input filter", true),
    pin("LATHE_INDEX", "PB0", "TIM3_CH3 input capture (AF2): the count latched in hardware at the rising edge", true),
    pin("CUTTER_STEP", "PA8", "TIM1_CH1, pulses from DMA-fed segments", true),
    pin("CUTTER_DIR", "PA9", "TIM1_CH2, changes on a segment boundary, never while STEP is high", true),
    pin("CUTTER_ENABLE", "PB13", "push-pull output, inactive at reset", true),
    pin("ESTOP", "PB14", "EXTI14, pull-up, normally closed to GND: open = stop", true),
    pin("DRIVE_ALARM", "PB15", "EXTI15, pull-up, alarm pulls to GND", true),
    pin("CUTTER_A", "PB6", "TIM4_CH1, encoder mode (BLDC mode)", true),
    pin("CUTTER_B", "PB7", "TIM4_CH2, encoder mode (BLDC mode)", true),
    pin("BLDC_PWM", "PB8", "TIM10_CH1, ESC pulse 1-2 ms at 50 Hz (BLDC mode)", true),
    pin("X_STEP", "PB4", "push-pull output, one tick-long pulse (X axis cam)", true),
    pin("X_DIR", "PB5", "push-pull output (X axis cam)", true),
    pin("USB_DM", "PA11", "USB OTG FS", true),
    pin("USB_DP", "PA12", "USB OTG FS", true),
    pin("STATUS_LED", "PC13", "active low, on-board LED", false),
];

/// Control tick rate: 25 kHz (40 µs), above the 20 kHz floor of the design.
pub const TICK_HZ: u32 = 25_000;
/// System clock from the 25 MHz HSE crystal: 96 MHz, so USB gets exactly
/// 48 MHz from the same PLL. Every timer runs at 96 MHz.
pub const SYSCLK_HZ: u32 = 96_000_000;

/// Timers the firmware uses, and what for (none shared).
pub const TIMERS: &[(&str, &str)] = &[
    ("TIM1", "STEP (CH1) and DIR (CH2): segments loaded by DMA2 stream 5 at each update event"),
    ("TIM2", "counts the step pulses (slave of TIM1's OC1REF via ITR0)"),
    ("TIM3", "lathe encoder (encoder mode, input filter)"),
    ("TIM4", "cutter encoder (BLDC mode)"),
    ("TIM5", "embassy time driver"),
    ("TIM10", "ESC PWM (BLDC mode)"),
    ("TIM11", "control tick, 25 kHz update interrupt at the highest priority"),
];

/// Interrupt priorities, in one place (0 is the most urgent; the NVIC of
/// the STM32F411 has 16 levels). The control tick is strictly above every
/// other interrupt but the E-stop/alarm one, which may share its level
/// (both only stop things, and equal levels do not pre-empt each other).
/// `app` applies this map at boot and checks every enabled interrupt
/// against it.
pub const PRIORITIES: &[(&str, u8)] = &[
    ("TIM1_TRG_COM_TIM11", 0), // control tick
    ("EXTI15_10", 0),          // E-stop, drive alarm
    ("TIM5", 1),               // embassy's time driver
    ("OTG_FS", 2),             // USB console
    ("USART6", 6),             // planning executor (InterruptExecutor)
];

/// The interrupt that may share the tick's level.
pub const SHARES_TICK: &str = "EXTI15_10";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_estop_shares_the_ticks_priority_and_nothing_outranks_it() {
        let tick = PRIORITIES.iter().find(|p| p.0 == "TIM1_TRG_COM_TIM11").unwrap().1;
        for (name, level) in PRIORITIES {
            assert!(*level < 16, "{name}: the NVIC has 16 levels");
            assert!(*level >= tick, "{name} outranks the tick");
            if *level == tick && *name != "TIM1_TRG_COM_TIM11" {
                assert_eq!(*name, SHARES_TICK);
            }
        }
    }

    #[test]
    fn every_pin_is_used_once() {
        for (i, a) in PINS.iter().enumerate() {
            for b in &PINS[i + 1..] {
                assert_ne!(a.pin, b.pin, "{} and {} share a pin", a.signal, b.signal);
            }
        }
    }

    #[test]
    fn lathe_side_inputs_are_five_volt_tolerant() {
        for p in PINS.iter().filter(|p| p.signal.starts_with("LATHE") || p.signal == "ESTOP") {
            assert!(p.five_volt_tolerant, "{} on {}", p.signal, p.pin);
        }
    }
}
