//! The rules that join several settings, and, for a `set` that breaks one,
//! the bound of the setting being set given the others: the console says
//! it (`console::misfit`), so the machinist need not do the sum.

use super::{range, BldcOut, Config, ConfigError, DriveKind};

/// A limit that joins several settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Rule {
    /// max-rate x 2 x pulse <= 1 s: a step is a pulse high and as long low
    PulseRate,
    /// max-rpm x ratio x steps / 60 <= max-rate: the motor keeps up with
    /// the lathe at its declared top speed
    StepRate,
    /// start-rate <= max-rate
    StartRate,
    /// with `drive bldc`: max-rpm x ratio / 60 <= the drive's command rate
    /// (a drive corrected less than once per cutter turn cannot hold its
    /// phase: at 3 000 rpm a 50 Hz ESC gets one command per cutter turn)
    CommandRate,
}

/// What a setting must be for a rule to hold, the others as they are:
/// at most or at least `num / den` (a fraction: the ratio's bound is one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bound {
    pub at_most: bool,
    pub num: u64,
    pub den: u64,
}

const fn at_most(num: u64, den: u64) -> Option<Bound> {
    Some(Bound { at_most: true, num, den })
}

const fn at_least(num: u64, den: u64) -> Option<Bound> {
    Some(Bound { at_most: false, num, den })
}

impl Bound {
    /// True if `self` is the tighter of two bounds on the same side.
    fn tighter_than(&self, other: &Bound) -> bool {
        let (a, b) = (self.num as u128 * other.den as u128, other.num as u128 * self.den as u128);
        if self.at_most {
            a < b
        } else {
            a > b
        }
    }
}

const ONE_SECOND_NS: u64 = 1_000_000_000;

impl Rule {
    /// In the order `Config::validate` checks them.
    pub const ALL: [Rule; 4] = [Rule::PulseRate, Rule::StepRate, Rule::StartRate, Rule::CommandRate];

    /// True if the rule holds for `c`.
    pub fn holds(self, c: &Config) -> bool {
        let (rpm, num, den) = (c.max_lathe_rpm as u64, c.ratio.num() as u64, c.ratio.den() as u64);
        let rate = c.max_step_rate_hz as u64;
        match self {
            Rule::PulseRate => rate * 2 * c.step_pulse_ns as u64 <= ONE_SECOND_NS,
            Rule::StepRate => rpm * num * c.motor_steps_per_rev as u64 <= 60 * den * rate,
            Rule::StartRate => c.start_rate_hz <= c.max_step_rate_hz,
            Rule::CommandRate => c.drive != DriveKind::Bldc || rpm * num <= 60 * den * frame_hz(c),
        }
    }

    /// The setting `Config::validate` names, and why, as the host's flags
    /// quote it.
    pub fn error(self) -> ConfigError {
        match self {
            Rule::PulseRate => range("max-rate", "does not fit with the others: max-rate x 2 x pulse must not exceed 1 s (a step is a pulse high and as long low)"),
            Rule::StepRate => range("ratio", "does not fit with the others: max-rpm x ratio x steps/60 must not exceed max-rate (the motor must keep up at the lathe's top speed)"),
            Rule::StartRate => range("start-rate", "does not fit with the others: start-rate must not exceed max-rate"),
            Rule::CommandRate => range("bldc-out", super::bldc_out::RATE),
        }
    }

    /// The rule in a few words, after a bound (the bound says the rest).
    pub fn formula(self) -> &'static str {
        match self {
            Rule::PulseRate => "max-rate x 2 x pulse must not exceed 1 s: a step is a pulse high and as long low",
            Rule::StepRate => "max-rpm x ratio x steps/60 must not exceed max-rate: the motor must keep up at the lathe's top speed",
            Rule::StartRate => "start-rate must not exceed max-rate",
            Rule::CommandRate => "the drive must take a command at least once per cutter revolution: max-rpm x ratio / 60 must not exceed 50 Hz for esc50, 400 for esc400, 2000 for oneshot125, pwm-hz for pwm",
        }
    }

    /// The settings the rule joins in `c` (`pwm-hz` only with `bldc-out
    /// pwm`), as `set` names them.
    pub fn settings(self, c: &Config) -> &'static [&'static str] {
        match self {
            Rule::PulseRate => &["max-rate", "pulse"],
            Rule::StepRate => &["max-rpm", "ratio", "steps", "max-rate"],
            Rule::StartRate => &["start-rate", "max-rate"],
            Rule::CommandRate if c.bldc_out == BldcOut::Pwm => &["max-rpm", "ratio", "bldc-out", "pwm-hz"],
            Rule::CommandRate => &["max-rpm", "ratio", "bldc-out"],
        }
    }

    /// The bound the rule sets on `setting`, the others as in `c`; None for
    /// a setting that is no number in it (`drive`, `bldc-out`) or not in it.
    pub fn bound(self, setting: &str, c: &Config) -> Option<Bound> {
        let (rpm, num, den) = (c.max_lathe_rpm as u64, c.ratio.num() as u64, c.ratio.den() as u64);
        let (rate, steps) = (c.max_step_rate_hz as u64, c.motor_steps_per_rev as u64);
        match (self, setting) {
            (Rule::PulseRate, "max-rate") => at_most(ONE_SECOND_NS, 2 * c.step_pulse_ns as u64),
            (Rule::PulseRate, "pulse") => at_most(ONE_SECOND_NS, 2 * rate),
            (Rule::StepRate, "max-rpm") => at_most(60 * den * rate, num * steps),
            (Rule::StepRate, "ratio") => at_most(60 * rate, rpm * steps),
            (Rule::StepRate, "steps") => at_most(60 * den * rate, rpm * num),
            (Rule::StepRate, "max-rate") => at_least(rpm * num * steps, 60 * den),
            (Rule::StartRate, "start-rate") => at_most(rate, 1),
            (Rule::StartRate, "max-rate") => at_least(c.start_rate_hz as u64, 1),
            (Rule::CommandRate, "max-rpm") => at_most(60 * den * frame_hz(c), num),
            (Rule::CommandRate, "ratio") => at_most(60 * frame_hz(c), rpm),
            (Rule::CommandRate, "pwm-hz") if c.bldc_out == BldcOut::Pwm => at_least(rpm * num, 60 * den),
            _ => None,
        }
    }
}

fn frame_hz(c: &Config) -> u64 {
    c.bldc_out.frame_hz(c.pwm_hz) as u64
}

/// A `set` of a value valid alone that breaks a rule with the others: the
/// setting, the rule that binds it most tightly, and the settings it would
/// have made (the others' values are the board's own).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Misfit {
    pub setting: &'static str,
    pub rule: Rule,
    pub config: Config,
}

impl Misfit {
    /// The misfit of `c`, made by setting `setting`; None if every rule
    /// holds. Of the rules broken, the one whose bound on `setting` is the
    /// tightest (lowering max-rate can break two: the higher of their
    /// floors is the one that fits both), else the first.
    pub fn of(setting: &'static str, c: &Config) -> Option<Misfit> {
        let mut broken = Rule::ALL.into_iter().filter(|r| !r.holds(c));
        let mut rule = broken.next()?;
        for r in broken {
            if let (Some(b), Some(now)) = (r.bound(setting, c), rule.bound(setting, c)) {
                if b.tighter_than(&now) {
                    rule = r;
                }
            }
        }
        Some(Misfit { setting, rule, config: *c })
    }

    /// The refusal as a `ConfigError`: the setting and the rule's words.
    pub fn error(&self) -> ConfigError {
        ConfigError { field: self.setting, allowed: self.rule.error().allowed }
    }

    /// The bound on the setting, if it is a number of the rule.
    pub fn bound(&self) -> Option<Bound> {
        self.rule.bound(self.setting, &self.config)
    }
}

/// Why a `set` was refused: its value alone, or with the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetError {
    Alone(ConfigError),
    Together(Misfit),
}

impl SetError {
    pub fn error(self) -> ConfigError {
        match self {
            SetError::Alone(e) => e,
            SetError::Together(m) => m.error(),
        }
    }
}

impl From<ConfigError> for SetError {
    fn from(e: ConfigError) -> SetError {
        SetError::Alone(e)
    }
}

#[cfg(test)]
#[path = "together_tests.rs"]
mod tests;
