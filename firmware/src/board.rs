//! The Black Pill pin map, in one place (the book's wiring table is generated from it: firmware/book).
//!
//! 5 V tolerant ("FT") pins are used for every input that comes from the
//! lathe side, which is often 5 V logic. PA6/PA7 (TIM3) and PB6/PB7 (TIM4)
//! are FT on the STM32F411 (datasheet DS10314, table 9).

/// One pin assignment: the signal, the MCU pin, its role, and how the
/// firmware configures it (checked against the registers the real image
/// writes by `.ci/emu`: `emu/src/checks.rs` reads this table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pin {
    pub signal: &'static str,
    pub pin: &'static str,
    pub function: &'static str,
    pub five_volt_tolerant: bool,
    pub mode: Mode,
    pub pull: Pull,
}

/// GPIOx_MODER's setting of a pin (RM0383 §8.4.1), with the alternate
/// function number for GPIOx_AFRL/AFRH (§8.4.9, DS10314 table 9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Input,
    Output,
    Alternate(u8),
}

/// GPIOx_PUPDR's setting of a pin (RM0383 §8.4.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pull {
    None,
    Up,
    Down,
}

impl Mode {
    /// The two MODER bits: 00 input, 01 output, 10 alternate function.
    pub const fn moder(self) -> u32 {
        match self {
            Mode::Input => 0b00,
            Mode::Output => 0b01,
            Mode::Alternate(_) => 0b10,
        }
    }

    pub const fn af(self) -> Option<u8> {
        match self {
            Mode::Alternate(n) => Some(n),
            _ => None,
        }
    }
}

impl Pull {
    /// The two PUPDR bits: 00 none, 01 pull-up, 10 pull-down.
    pub const fn pupdr(self) -> u32 {
        match self {
            Pull::None => 0b00,
            Pull::Up => 0b01,
            Pull::Down => 0b10,
        }
    }
}

impl Pin {
    /// Port letter and pin number, from the name ("PB13" -> ('B', 13)).
    pub fn port_and_index(&self) -> (char, u8) {
        let b = self.pin.as_bytes();
        let index = self.pin[2..].parse().unwrap_or(u8::MAX);
        (b[1] as char, index)
    }
}

const AF1: Mode = Mode::Alternate(1); // TIM1, TIM2
const AF2: Mode = Mode::Alternate(2); // TIM3, TIM4, TIM5
const AF3: Mode = Mode::Alternate(3); // TIM9, TIM10, TIM11
const AF10: Mode = Mode::Alternate(10); // OTG_FS

const fn pin(signal: &'static str, pin: &'static str, function: &'static str, ft: bool, mode: Mode, pull: Pull) -> Pin {
    Pin { signal, pin, function, five_volt_tolerant: ft, mode, pull }
}

/// The full pin map. `main.rs` takes the same pins by name.
pub const PINS: &[Pin] = &[
    pin(
        "LATHE_A",
        "PA6",
        "TIM3_CH1, encoder mode, input filter; each rising edge latches the count and its µs in hardware (edgetime)",
        true,
        AF2,
        Pull::None,
    ),
    pin("LATHE_B", "PA7", "TIM3_CH2, encoder mode, input filter", true, AF2, Pull::None),
    pin(
        "LATHE_INDEX",
        "PB0",
        "TIM3_CH3 input capture (AF2): the count latched in hardware at the rising edge",
        true,
        AF2,
        Pull::Down,
    ),
    pin("CUTTER_STEP", "PA8", "TIM1_CH1, pulses from DMA-fed segments", true, AF1, Pull::None),
    pin(
        "CUTTER_DIR",
        "PA9",
        "TIM1_CH2, changes on a segment boundary, never while STEP is high",
        true,
        AF1,
        Pull::None,
    ),
    pin("CUTTER_ENABLE", "PB13", "push-pull output, inactive at reset", true, Mode::Output, Pull::None),
    pin("ESTOP", "PB14", "EXTI14, pull-up, normally closed to GND: open = stop", true, Mode::Input, Pull::Up),
    pin("DRIVE_ALARM", "PB15", "EXTI15, pull-up, alarm pulls to GND", true, Mode::Input, Pull::Up),
    pin("CUTTER_A", "PB6", "TIM4_CH1, encoder mode (BLDC mode, or the lost-step alarm)", true, AF2, Pull::None),
    pin("CUTTER_B", "PB7", "TIM4_CH2, encoder mode (BLDC mode, or the lost-step alarm)", true, AF2, Pull::None),
    pin(
        "BLDC_PWM",
        "PB8",
        "TIM10_CH1: the BLDC drive's command (bldc-out: an RC ESC pulse at 50 or 400 Hz, OneShot125, or a 1-20 kHz PWM)",
        true,
        AF3,
        Pull::None,
    ),
    // an output: taken as 3.3 V only, like the self-test's pins
    pin(
        "BLDC_DIR",
        "PB1",
        "push-pull output (a floating input from reset until boot drives it low): the cutter's sense for a driver's DIR input (low = dir same)",
        false,
        Mode::Output,
        Pull::None,
    ),
    pin("X_STEP", "PB4", "push-pull output, one tick-long pulse (X axis cam)", true, Mode::Output, Pull::None),
    pin("X_DIR", "PB5", "push-pull output (X axis cam)", true, Mode::Output, Pull::None),
    pin("USB_DM", "PA11", "USB OTG FS", true, AF10, Pull::None),
    pin("USB_DP", "PA12", "USB OTG FS", true, AF10, Pull::None),
    pin("STATUS_LED", "PC13", "active low, on-board LED", false, Mode::Output, Pull::None),
    pin(
        "EXT_LED",
        "PA10",
        "push-pull output, active high: an optional panel LED (with a resistor)",
        true,
        Mode::Output,
        Pull::None,
    ),
    // the bench self-test's lathe (quadgen): jumpered to PA6, PA7 and PB0;
    // A and B are inputs with pull-downs but while a test plays (TIM9, AF3);
    // taken as 3.3 V only (they connect to nothing but the board's inputs)
    pin("SELFTEST_A", "PA2", "input, pull-down; TIM9_CH1 (AF3) while selftest plays", false, Mode::Input, Pull::Down),
    pin("SELFTEST_B", "PA3", "input, pull-down; TIM9_CH2 (AF3) while selftest plays", false, Mode::Input, Pull::Down),
    pin(
        "SELFTEST_INDEX",
        "PA4",
        "push-pull output, low; written by TIM9's update interrupt",
        false,
        Mode::Output,
        Pull::None,
    ),
    // the keys at the lathe: switches to GND, read every ms at low priority (keys.rs)
    pin("KEY_ENGAGE", "PB12", "key input, pull-up, to GND when pressed", true, Mode::Input, Pull::Up),
    pin("KEY_STOP", "PB10", "key input, pull-up, to GND when pressed", true, Mode::Input, Pull::Up),
    pin("KEY_PHASE_PLUS", "PB9", "key input, pull-up, to GND when pressed", true, Mode::Input, Pull::Up),
    pin("KEY_PHASE_MINUS", "PA15", "key input, pull-up, to GND when pressed", true, Mode::Input, Pull::Up),
];

/// Control tick rate: 20 kHz (50 µs), from the clock tree (`clocks::TIMING`).
pub const TICK_HZ: u32 = crate::clocks::TIMING.tick_hz;
/// System clock from the 25 MHz HSE crystal: 96 MHz, so USB gets exactly
/// 48 MHz from the same PLL. Every timer runs at 96 MHz (`clocks`).
pub const SYSCLK_HZ: u32 = crate::clocks::CLOCKS.sysclk_hz();

/// Timers the firmware uses, and what for (none shared but TIM5: embassy's
/// time driver uses its counter, CC1 and CC2; the edge times only read its
/// counter through channel 3, with its slave mode off, `edgetime`).
pub const TIMERS: &[(&str, &str)] = &[
    ("TIM1", "STEP (CH1) and DIR (CH2): segments loaded by DMA2 stream 5 at each update event"),
    ("TIM2", "counts the step pulses (slave of TIM1's OC1REF via ITR0)"),
    (
        "TIM3",
        "lathe encoder (encoder mode, input filter); CC1 captures the count at A's rising edge, CC3 at the index's; TRGO pulses at each CC1 capture (edgetime)",
    ),
    ("TIM4", "cutter encoder (BLDC mode, or on a stepper's shaft for the lost-step alarm)"),
    (
        "TIM5",
        "embassy time driver (1 MHz, CC1 and CC2); CC3 timestamps the lathe's A rises: TRC from TIM3's TRGO via ITR1 (edgetime)",
    ),
    ("TIM9", "the bench self-test's quadrature generator (CH1 PA2, CH2 PA3)"),
    ("TIM10", "the BLDC drive's command on CH1: PWM mode 1, frame and pulse range by bldc-out (bldcout)"),
    ("TIM11", "control tick, 20 kHz update interrupt below only the E-stop"),
];

/// Interrupt priorities, in one place (0 is the most urgent; the NVIC of
/// the STM32F411 has 16 levels). The E-stop/alarm interrupt is above
/// everything, so STEP stops at the EXTI's latency even mid-tick; the
/// control tick is next, strictly above every other interrupt; then the
/// step plan the tick leaves (`PLAN_IRQ`), above everything that takes the
/// global critical section (`app/cs.rs`), so that nothing but the E-stop
/// and the next tick comes between the tick and its plan. Neither
/// takes a lock the other holds: the E-stop only writes the outputs, and
/// the tick re-applies the stop if the E-stop ran inside it
/// (`app/tick.rs`). `app` applies this map at boot and checks every
/// enabled interrupt against it.
pub const PRIORITIES: &[(&str, u8)] = &[
    (ESTOP_IRQ, ESTOP_LEVEL), // E-stop, drive alarm
    (TICK_IRQ, TICK_LEVEL),   // control tick
    (PLAN_IRQ, PLAN_LEVEL),   // the tick's step plan
    ("TIM5", 3),              // embassy's time driver
    ("TIM1_BRK_TIM9", 3),     // the self-test's generator (quadgen)
    ("OTG_FS", 4),            // USB console
    ("USART6", 6),            // planning executor (InterruptExecutor)
];

/// The E-stop and drive-alarm interrupt (EXTI lines 14 and 15).
pub const ESTOP_IRQ: &str = "EXTI15_10";
/// The E-stop's level: the most urgent, above the tick and its lock.
pub const ESTOP_LEVEL: u8 = 0;
/// The control tick's interrupt (TIM11's update shares TIM1's vector).
pub const TICK_IRQ: &str = "TIM1_TRG_COM_TIM11";
/// The tick's level: next to the E-stop. The tick's lock masks this level
/// and below (`app/tick.rs`); `app/cs.rs` masks the levels below the
/// tick's step plan's (`PLAN_LEVEL`).
pub const TICK_LEVEL: u8 = 1;
// The tick's lock writes BASEPRI = TICK_LEVEL << 4, which masks that level
// and below (PM0214 §2.1.3; 0 would mask nothing): the E-stop must be more
// urgent to stay deliverable under it.
const _: () = assert!(ESTOP_LEVEL < TICK_LEVEL && TICK_LEVEL > 0);
/// The step plan's interrupt, pended by the tick (`app/tick/plan.rs`): a
/// vector no peripheral of the board asserts (USART2 is not clocked), as
/// embassy's `InterruptExecutor` takes USART6's.
pub const PLAN_IRQ: &str = "USART2";
/// The plan's level: next below the tick, which pre-empts it, and above
/// the global critical section (`app/cs.rs` masks the levels below it),
/// so only the tick's lock holds it off, and the tick never waits for it.
pub const PLAN_LEVEL: u8 = TICK_LEVEL + 1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_estop_outranks_the_tick_and_nothing_shares_its_level() {
        let tick = PRIORITIES.iter().find(|p| p.0 == TICK_IRQ).unwrap().1;
        for (name, level) in PRIORITIES {
            assert!(*level < 16, "{name}: the NVIC has 16 levels");
            if *name == ESTOP_IRQ {
                assert!(*level < tick, "the E-stop must pre-empt the tick");
            } else if *name != TICK_IRQ {
                assert!(*level > tick, "{name} reaches the tick's level");
            }
        }
    }

    #[test]
    fn the_estop_is_above_the_ticks_lock_and_the_global_critical_section() {
        // the tick's lock (app/tick/shared.rs) writes BASEPRI = TICK_LEVEL << 4,
        // which masks TICK_LEVEL and below (PM0214 §2.1.3): the E-stop must
        // stay deliverable under it, so it must be strictly more urgent
        let level = |n: &str| PRIORITIES.iter().find(|p| p.0 == n).unwrap().1;
        assert_eq!(level(ESTOP_IRQ), ESTOP_LEVEL);
        assert_eq!(level(TICK_IRQ), TICK_LEVEL);
    }

    #[test]
    fn the_plan_is_next_below_the_tick_and_alone_at_its_level() {
        // the plan takes no lock (app/tick/plan.rs): only the tick may
        // pre-empt it, and nothing that takes the critical section (cs.rs
        // masks the levels below PLAN_LEVEL) may share or outrank its level
        let level = |n: &str| PRIORITIES.iter().find(|p| p.0 == n).unwrap().1;
        assert_eq!(level(PLAN_IRQ), TICK_LEVEL + 1);
        for (name, l) in PRIORITIES {
            if ![ESTOP_IRQ, TICK_IRQ, PLAN_IRQ].contains(name) {
                assert!(*l > PLAN_LEVEL, "{name} reaches the plan's level");
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

    /// The alternate function numbers of DS10314 table 9 for the
    /// peripheral each pin's function names.
    fn af_of(function: &str) -> Option<u8> {
        [
            ("TIM10_", 3),
            ("TIM11_", 3),
            ("TIM9_", 3),
            ("TIM1_", 1),
            ("TIM2_", 1),
            ("TIM3_", 2),
            ("TIM4_", 2),
            ("TIM5_", 2),
            ("USB OTG FS", 10),
        ]
        .iter()
        .find(|(p, _)| function.starts_with(p))
        .map(|&(_, af)| af)
    }

    #[test]
    fn each_pin_mode_agrees_with_its_function() {
        for p in PINS {
            let (port, index) = p.port_and_index();
            assert!(('A'..='C').contains(&port) && index < 16, "{}: {}", p.signal, p.pin);
            match p.mode {
                Mode::Alternate(af) => assert_eq!(Some(af), af_of(p.function), "{} on {}", p.signal, p.pin),
                Mode::Output => {
                    assert!(p.function.contains("output") || p.function.contains("LED"), "{}", p.signal);
                    assert_eq!(af_of(p.function), None, "{}", p.signal);
                }
                Mode::Input => {
                    let f = p.function;
                    assert!(
                        f.starts_with("EXTI") || f.starts_with("key input") || f.starts_with("input"),
                        "{}",
                        p.signal
                    )
                }
            }
            assert_eq!(p.pull == Pull::Up, p.function.contains("pull-up"), "{}", p.signal);
        }
    }

    #[test]
    fn register_encodings_are_the_manuals() {
        assert_eq!((Mode::Input.moder(), Mode::Output.moder(), AF1.moder()), (0, 1, 2));
        assert_eq!((Pull::None.pupdr(), Pull::Up.pupdr(), Pull::Down.pupdr()), (0, 1, 2));
        assert_eq!(AF10.af(), Some(10));
        assert_eq!(Mode::Output.af(), None);
    }

    #[test]
    fn lathe_side_inputs_are_five_volt_tolerant() {
        for p in PINS.iter().filter(|p| p.signal.starts_with("LATHE") || p.signal == "ESTOP") {
            assert!(p.five_volt_tolerant, "{} on {}", p.signal, p.pin);
        }
    }
}
