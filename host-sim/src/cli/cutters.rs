//! One rule for every flag that belongs to one kind of cutter: given with
//! the other kind (`--drive`), it is refused, naming it, not ignored.
//! `simulate` and `device setup` list their flags with the cutter each is
//! for, and both refuse through `refuse_others`.

use super::errors::{CliError, CliResult};
use polyturn_sync::DriveKind;

/// The kind of cutter a flag is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum For {
    Stepper,
    Bldc,
    /// a BLDC fed a PWM (`--bldc-out pwm`): an RC ESC's frame is fixed
    Pwm,
}

impl For {
    fn why(self) -> &'static str {
        match self {
            For::Stepper => "is for a stepper (--drive stepper)",
            For::Bldc => "is for a BLDC cutter (--drive bldc)",
            For::Pwm => "is for --bldc-out pwm (an RC ESC's frame is fixed)",
        }
    }

    fn fits(self, drive: DriveKind, pwm: bool) -> bool {
        match self {
            For::Stepper => drive != DriveKind::Bldc,
            For::Bldc => drive == DriveKind::Bldc,
            For::Pwm => drive == DriveKind::Bldc && pwm,
        }
    }
}

/// The first flag given (name, for, given) that does not fit `drive`
/// (fed a PWM or not), refused with what it is for.
pub fn refuse_others(drive: DriveKind, pwm: bool, flags: &[(&str, For, bool)]) -> CliResult<()> {
    match flags.iter().find(|(_, f, given)| *given && !f.fits(drive, pwm)) {
        // a BLDC-only flag with a stepper is a BLDC's, though it also needs pwm
        Some((name, For::Pwm, _)) if drive != DriveKind::Bldc => Err(CliError::flag(name, For::Bldc.why())),
        Some((name, f, _)) => Err(CliError::flag(name, f.why())),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flag_for_the_other_cutter_is_refused_and_one_for_this_one_taken() {
        let flags = [("start-rate", For::Stepper, true), ("pwm-hz", For::Pwm, false)];
        assert_eq!(refuse_others(DriveKind::Stepper, false, &flags), Ok(()));
        let e = refuse_others(DriveKind::Bldc, true, &flags).unwrap_err().0;
        assert_eq!(e, "--start-rate is for a stepper (--drive stepper)");
        let pwm = [("pwm-hz", For::Pwm, true)];
        assert_eq!(refuse_others(DriveKind::Bldc, true, &pwm), Ok(()));
        assert!(refuse_others(DriveKind::Bldc, false, &pwm).unwrap_err().0.contains("is for --bldc-out pwm"));
        assert!(refuse_others(DriveKind::Stepper, false, &pwm).unwrap_err().0.contains("is for a BLDC cutter"));
    }
}
