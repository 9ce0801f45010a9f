//! The console's table of settings: every name `get` and `set` take, in
//! `get` order, with the values each takes. A number's range is written
//! once, here: the console checks it and says it when refusing (`set`),
//! and the host's flags, the guided setup's prompts and `--help` take the
//! same range from this table, so none can take a value the board refuses.

use super::ConfigError;

/// A number setting's range and the console's words for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    /// the setting's name, as `set` takes it
    pub name: &'static str,
    pub lo: u32,
    pub hi: u32,
    /// `lo..=hi` and the unit, made from the same two numbers
    pub allowed: &'static str,
}

/// A span whose words are made from its own bounds (`concat!` of the
/// literals), so the text cannot say another range than the check holds.
macro_rules! span {
    ($name:literal, $lo:literal, $hi:literal, $rest:literal) => {
        Span { name: $name, lo: $lo, hi: $hi, allowed: concat!($lo, "..=", $hi, $rest) }
    };
}

impl Span {
    pub const fn contains(&self, v: u32) -> bool {
        v >= self.lo && v <= self.hi
    }

    /// The refusal: this setting and its range.
    pub const fn error(&self) -> ConfigError {
        ConfigError { field: self.name, allowed: self.allowed }
    }

    /// `v` if it is in the range, else the refusal.
    pub const fn check(&self, v: u32) -> Result<u32, ConfigError> {
        if self.contains(v) {
            Ok(v)
        } else {
            Err(self.error())
        }
    }
}

pub const CPR: Span = span!("cpr", 4, 1000000, " counts per lathe rev");
pub const STEPS: Span = span!("steps", 1, 1000000, " steps per cutter rev");
pub const EDGES: Span = span!("edges", 1, 12, "");
pub const MAX_RATE: Span = span!("max-rate", 1, 250000, " Hz");
pub const MAX_ACCEL: Span = span!("max-accel", 10, 50000000, " steps/s^2");
pub const FERROR: Span = span!("ferror", 1, 1000000, " steps");
pub const DIR_SETUP: Span = span!("dir-setup", 0, 100000, " ns");
pub const PULSE: Span = span!("pulse", 100, 10000, " ns");
pub const MAX_RPM: Span = span!("max-rpm", 1, 10000, " rpm");
/// `off` (0) is also taken: no cutter encoder
pub const CUTTER_CPR: Span = span!("cutter-cpr", 4, 1000000, " counts per cutter rev, or off");
pub const LOST_STEPS: Span = span!("lost-steps", 1, 1000000, " steps");
pub const START_RATE: Span = span!("start-rate", 0, 250000, " Hz (0: off)");
/// and a divisor of the timer's clock (`bldc_out::check_pwm_hz`)
pub const PWM_HZ: Span = span!(
    "pwm-hz",
    1000,
    20000,
    " Hz, a divisor of 96000000 (the timer's clock), e.g. 1000 2000 4000 5000 8000 10000 16000 20000"
);
pub const BLDC_TAU: Span = span!("bldc-tau", 1, 1000, " ms (the drive's time to 63 % of a speed step)");

/// A span and its refusal in full (`name lo..=hi rest`), from one set of
/// literals: for a command's number, which the console refuses as a whole.
macro_rules! span_and_refusal {
    ($name:literal, $lo:literal, $hi:literal, $rest:literal) => {
        (span!($name, $lo, $hi, $rest), concat!($name, " ", $lo, "..=", $hi, $rest))
    };
}

/// `divide N`'s number of divisions: a command's range, not a setting
/// (nothing is saved). The cpr/4 bound keeps each division's tolerance
/// (± one count) clear of the next (`Controller::start_divide`).
const DIVIDE_AND_REFUSAL: (Span, &str) =
    span_and_refusal!("divide", 1, 3600, " divisions of a turn, at most cpr/4 (4 counts or more apart)");
pub const DIVIDE: Span = DIVIDE_AND_REFUSAL.0;
/// `divide`'s refusal: the range, whatever was wrong with the number
pub const DIVIDE_REFUSAL: &str = DIVIDE_AND_REFUSAL.1;

pub const RATIO: &str =
    "an integer, p/q, p:q or a decimal like 2.5 (up to 6 decimals), numerator and denominator 1..=1000 after reduction";
pub const DIR: &str = "same or opposite";
pub const PHASE: &str = "-360..=360 degrees of the cutter, up to 3 decimals";
pub const DRIVE: &str = "stepper, bldc or none";
pub const ENABLE: &str = "high or low (the active level)";
pub const BLDC_OUT: &str = "esc50, esc400, oneshot125 or pwm";

/// One setting: its name, and its range if it is a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Setting {
    pub name: &'static str,
    pub span: Option<Span>,
    /// what it takes, in the console's words
    pub allowed: &'static str,
}

const fn number(s: Span) -> Setting {
    Setting { name: s.name, span: Some(s), allowed: s.allowed }
}

const fn words(name: &'static str, allowed: &'static str) -> Setting {
    Setting { name, span: None, allowed }
}

/// Every setting, in `get` order.
pub const SETTINGS: [Setting; 20] = [
    number(CPR),
    number(STEPS),
    words("ratio", RATIO),
    words("dir", DIR),
    number(EDGES),
    number(MAX_RATE),
    number(MAX_ACCEL),
    number(FERROR),
    words("phase", PHASE),
    words("drive", DRIVE),
    number(DIR_SETUP),
    number(PULSE),
    words("enable", ENABLE),
    number(MAX_RPM),
    number(CUTTER_CPR),
    number(LOST_STEPS),
    number(START_RATE),
    words("bldc-out", BLDC_OUT),
    number(PWM_HZ),
    number(BLDC_TAU),
];

/// The settable names, in `get` order (the table's).
pub const NAMES: [&str; SETTINGS.len()] = {
    let mut names = [""; SETTINGS.len()];
    let mut i = 0;
    while i < SETTINGS.len() {
        names[i] = SETTINGS[i].name;
        i += 1;
    }
    names
};

/// The setting called `name`.
pub fn setting(name: &str) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{bldc_out, Config};
    use std::format;
    use std::string::ToString;

    #[test]
    fn every_numbers_words_say_the_range_it_checks() {
        for s in SETTINGS.iter().filter_map(|s| s.span) {
            assert!(s.allowed.starts_with(&format!("{}..={}", s.lo, s.hi)), "{s:?}");
            assert_eq!((s.check(s.lo), s.check(s.hi)), (Ok(s.lo), Ok(s.hi)), "{s:?}");
            assert_eq!(s.check(s.hi + 1), Err(s.error()));
            if s.lo > 0 {
                assert_eq!(s.check(s.lo - 1).unwrap_err().field, s.name);
            }
        }
        assert!(PWM_HZ.allowed.contains(&format!("a divisor of {}", bldc_out::TIMER_HZ)));
    }

    #[test]
    fn the_console_refuses_each_number_past_its_range_in_the_tables_words() {
        for s in SETTINGS.iter().filter_map(|s| s.span) {
            let past = (s.hi as u64 + 1).to_string();
            let e = Config::default().with(s.name, &past).unwrap_err();
            assert_eq!((e.field, e.allowed), (s.name, s.allowed), "set {} {past}", s.name);
        }
        for w in SETTINGS.iter().filter(|s| s.span.is_none()) {
            let e = Config::default().with(w.name, "?").unwrap_err();
            assert_eq!(e.field, w.name);
            // the ratio's refusal says which of its rules failed; the others are the table's
            if w.name != "ratio" {
                assert_eq!(e.allowed, w.allowed, "set {} ?", w.name);
            }
        }
    }

    #[test]
    fn the_names_the_console_lists_are_the_tables() {
        let listed = NAMES.join(" ");
        assert!(crate::console::HELP.ends_with(&format!("names: {listed}")), "{}", crate::console::HELP);
        let unknown = Config::default().with("bogus", "1").unwrap_err();
        assert_eq!(unknown.allowed, format!("one of: {listed}"));
        assert_eq!(setting("pulse").and_then(|s| s.span), Some(PULSE));
        assert_eq!(setting("bogus"), None);
    }
}
