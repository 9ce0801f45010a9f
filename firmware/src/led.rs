//! The status LED (PC13, and any LED wired beside it) as a function of the
//! controller's state and time, so a machinist reads the board at a glance:
//!
//! | light | meaning |
//! |---|---|
//! | off | the control tick is not running |
//! | slow blink, 1 Hz | idle |
//! | fast blink, 5 Hz | engaging (catching up with the lathe) |
//! | steady on | synchronised |
//! | N short flashes, then a pause (every 3 s) | fault N (`fault_code`) |

use polyturn_sync::{Fault, State};

/// The blink code of each fault: the number of flashes.
pub fn fault_code(f: Fault) -> u32 {
    match f {
        Fault::Overspeed => 1,
        Fault::FollowingError => 2,
        Fault::EncoderImplausible => 3,
        Fault::EStop => 4,
        Fault::DriveAlarm => 5,
        Fault::Stall => 6,
        Fault::StepOutput => 7,
    }
}

/// Whether the LED is lit at `ms` (milliseconds since boot).
pub fn lit(state: State, tick_running: bool, ms: u32) -> bool {
    if !tick_running {
        return false;
    }
    match state {
        State::Idle | State::Disengaging => ms % 1000 < 500,
        State::Engaging => ms % 200 < 100,
        State::Synced => true,
        State::Fault(f) => {
            // flashes of 150 ms on, 150 ms off, in a 3 s frame: seven
            // flashes still leave a 0.9 s pause
            let t = ms % 3000;
            t < 300 * fault_code(f) && t % 300 < 150
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern(state: State, step: u32, span: u32) -> Vec<bool> {
        (0..span / step).map(|i| lit(state, true, i * step)).collect()
    }

    /// Counts the rising edges of the light over one 3 s frame.
    fn flashes(state: State) -> usize {
        let p = pattern(state, 10, 3000);
        p.windows(2).filter(|w| !w[0] && w[1]).count() + p[0] as usize
    }

    #[test]
    fn each_fault_flashes_its_own_number_of_times() {
        let all = [
            Fault::Overspeed,
            Fault::FollowingError,
            Fault::EncoderImplausible,
            Fault::EStop,
            Fault::DriveAlarm,
            Fault::Stall,
            Fault::StepOutput,
        ];
        for f in all {
            assert_eq!(flashes(State::Fault(f)), fault_code(f) as usize, "{}", f.name());
        }
        // the longest code still ends with a pause of at least 0.9 s
        assert!((2100..3000).all(|ms| !lit(State::Fault(Fault::StepOutput), true, ms)));
    }

    #[test]
    fn states_blink_at_their_own_rates_and_a_dead_tick_is_dark() {
        assert_eq!(flashes(State::Idle), 3);
        assert_eq!(flashes(State::Engaging), 15);
        assert!(pattern(State::Synced, 10, 3000).iter().all(|&l| l));
        assert!((0..2000).all(|ms| !lit(State::Synced, false, ms)));
    }
}
