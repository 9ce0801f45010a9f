//! States and faults. Idle → Engaging → Synced → Disengaging → Idle, and
//! Fault(kind) latched until cleared.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fault {
    /// the lathe's speed × ratio needs more than the motor's max rate
    Overspeed,
    /// the cutter fell behind the target by more than the limit: sync lost
    FollowingError,
    /// the lathe encoder jumped faster than the lathe can turn, or slipped
    /// against its index
    EncoderImplausible,
    EStop,
    DriveAlarm,
    /// the BLDC's encoder does not follow the speed command
    Stall,
    /// the step output's pulse count does not match what was planned: the
    /// hardware did not do what it was told
    StepOutput,
    /// the cutter's shaft encoder is further from the steps sent than
    /// `lost-steps`: the stepper lost steps (overload, a jam)
    LostSteps,
}

impl Fault {
    /// Every fault, in the order of their LED codes (`led::fault_code`).
    pub const ALL: [Fault; 8] = [
        Fault::Overspeed,
        Fault::FollowingError,
        Fault::EncoderImplausible,
        Fault::EStop,
        Fault::DriveAlarm,
        Fault::Stall,
        Fault::StepOutput,
        Fault::LostSteps,
    ];

    /// E-stop, alarm, a step-output fault and lost steps stop motion at
    /// once; the others ramp down.
    pub fn immediate(self) -> bool {
        matches!(self, Fault::EStop | Fault::DriveAlarm | Fault::StepOutput | Fault::LostSteps)
    }

    pub fn name(self) -> &'static str {
        match self {
            Fault::Overspeed => "overspeed",
            Fault::FollowingError => "following-error",
            Fault::EncoderImplausible => "encoder-implausible",
            Fault::EStop => "estop",
            Fault::DriveAlarm => "drive-alarm",
            Fault::Stall => "stall",
            Fault::StepOutput => "step-output",
            Fault::LostSteps => "lost-steps",
        }
    }

    /// What a machinist should check.
    pub fn reason(self) -> &'static str {
        match self {
            Fault::Overspeed => "lathe speed x ratio needs more than max-rate: slow the lathe",
            Fault::FollowingError => "cutter fell behind: motor too weak or max-accel too low",
            Fault::EncoderImplausible => "lathe encoder jumped or slipped: check wiring and max-rpm",
            Fault::EStop => "e-stop open: close it, then clear",
            Fault::DriveAlarm => "drive reports an alarm: check the drive, then clear",
            Fault::Stall => "cutter encoder not following: check motor and its encoder",
            Fault::StepOutput => "step pulses did not match the plan: a firmware or board fault, please report it",
            Fault::LostSteps => "the cutter's shaft is not where the steps put it: lost steps (overload, a jam, or the encoder's A/B swapped); check, then clear",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum State {
    Idle,
    Engaging,
    Synced,
    Disengaging,
    /// turning the cutter by a set angle, slowly (`jog`): the machinist
    /// checks its direction and that one commanded turn is one real turn
    Jogging,
    Fault(Fault),
}

impl State {
    pub fn name(self) -> &'static str {
        match self {
            State::Idle => "idle",
            State::Engaging => "engaging",
            State::Synced => "synced",
            State::Disengaging => "disengaging",
            State::Jogging => "jogging",
            State::Fault(_) => "fault",
        }
    }
}

#[cfg(test)]
mod tests;
