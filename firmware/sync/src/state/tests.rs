//! Fault and state names as the console prints them, the reasons the
//! manual's fault table quotes (docs/src/first-power-up.md, the board's reason),
//! and which faults stop at once (the table's "motion" column).

use super::*;

const ALL: [Fault; 8] = Fault::ALL;

#[test]
fn each_fault_has_its_console_name() {
    let names = ALL.map(Fault::name);
    assert_eq!(
        names,
        [
            "overspeed",
            "following-error",
            "encoder-implausible",
            "estop",
            "drive-alarm",
            "stall",
            "step-output",
            "lost-steps"
        ]
    );
}

#[test]
fn each_fault_gives_the_reason_the_manual_quotes() {
    let reasons = ALL.map(Fault::reason);
    assert_eq!(
        reasons,
        [
            "lathe speed x ratio needs more than max-rate: slow the lathe",
            "cutter fell behind: motor too weak or max-accel too low",
            "lathe encoder jumped or slipped: check wiring and max-rpm",
            "e-stop open: close it, then clear",
            "drive reports an alarm: check the drive, then clear",
            "cutter encoder not following: check motor and its encoder",
            "step pulses did not match the plan: a firmware or board fault, please report it",
            "the cutter's shaft is not where the steps put it: lost steps (overload, a jam, or the encoder's A/B swapped); check, then clear",
        ]
    );
}

#[test]
fn estop_alarm_step_output_and_lost_steps_stop_at_once_the_others_ramp_down() {
    let immediate = ALL.map(Fault::immediate);
    assert_eq!(immediate, [false, false, false, true, true, false, true, true]);
}

#[test]
fn each_state_has_its_console_name() {
    let states =
        [State::Idle, State::Engaging, State::Synced, State::Disengaging, State::Jogging, State::Fault(Fault::Stall)];
    assert_eq!(states.map(State::name), ["idle", "engaging", "synced", "disengaging", "jogging", "fault"]);
}
