//! The status LED (PC13, and any LED wired beside it) as a function of the
//! controller's state and time, so a machinist reads the board at a glance:
//!
//! | light | meaning |
//! |---|---|
//! | off | the control tick is not running |
//! | slow blink, 1 Hz | idle |
//! | fast blink, 5 Hz | engaging (catching up with the lathe) |
//! | blink, 2 Hz | jogging (`jog`) |
//! | steady on | synchronised |
//! | N short flashes, then a pause (every 3 s) | fault N (`fault_code`) |
//! | flicker, 10 Hz, for 1.5 s | a key press was refused (ENGAGE while faulted or too fast); then the state's own light |
//! | three long flashes, then 2.4 s dark (every 5 s) | the image in flash is damaged: it does not run (`damaged`, `seal`) |

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
        Fault::LostSteps => 8,
    }
}

/// How long a refusal flickers, ms.
pub const REFUSED_MS: u32 = 1_500;

/// Whether the LED is lit at `ms` (milliseconds since boot), with the time
/// of the last refused key press, if any.
pub fn lit(state: State, tick_running: bool, ms: u32, refused_at: Option<u32>) -> bool {
    if !tick_running {
        return false;
    }
    if refused_at.is_some_and(|t| ms.wrapping_sub(t) < REFUSED_MS) {
        return ms % 100 < 50;
    }
    match state {
        State::Idle | State::Disengaging => ms % 1000 < 500,
        State::Engaging => ms % 200 < 100,
        State::Jogging => ms % 500 < 250,
        State::Synced => true,
        State::Fault(f) => {
            // flashes of 150 ms on, 150 ms off, in a 3 s frame: seven
            // flashes still leave a 0.9 s pause
            let t = ms % 3000;
            t < 300 * fault_code(f) && t % 300 < 150
        }
    }
}

/// The light of a damaged image (`seal::verify` refused it), at `ms`:
/// three flashes of 600 ms, 400 ms apart, then 2.4 s dark: a 5 s frame.
/// Long where a fault's are short (150 ms), and in no state's rhythm.
pub fn damaged(ms: u32) -> bool {
    let t = ms % DAMAGED_FRAME_MS;
    t < 3000 && t % 1000 < 600
}

/// The step, ms, at which the damaged image's loop sets the LEDs, and
/// its frame.
pub const DAMAGED_STEP_MS: u32 = 100;
pub const DAMAGED_FRAME_MS: u32 = 5000;

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern(state: State, step: u32, span: u32) -> Vec<bool> {
        (0..span / step).map(|i| lit(state, true, i * step, None)).collect()
    }

    /// Counts the rising edges of the light over one 3 s frame.
    fn flashes(state: State) -> usize {
        let p = pattern(state, 10, 3000);
        p.windows(2).filter(|w| !w[0] && w[1]).count() + p[0] as usize
    }

    #[test]
    fn each_fault_flashes_its_own_number_of_times() {
        for (i, f) in Fault::ALL.into_iter().enumerate() {
            assert_eq!(flashes(State::Fault(f)), fault_code(f) as usize, "{}", f.name());
            // ALL is in the order of the codes, 1 to 7
            assert_eq!(fault_code(f) as usize, i + 1, "{}", f.name());
        }
        // the longest code still ends with a pause of at least 0.9 s
        assert!((2100..3000).all(|ms| !lit(State::Fault(Fault::StepOutput), true, ms, None)));
    }

    #[test]
    fn states_blink_at_their_own_rates_and_a_dead_tick_is_dark() {
        assert_eq!(flashes(State::Idle), 3);
        assert_eq!(flashes(State::Engaging), 15);
        assert!(pattern(State::Synced, 10, 3000).iter().all(|&l| l));
        assert!((0..2000).all(|ms| !lit(State::Synced, false, ms, None)));
        assert_eq!(flashes(State::Jogging), 6);
    }

    #[test]
    fn a_damaged_image_shows_three_long_flashes_unlike_any_other_light() {
        let frame: Vec<bool> = (0..5000).map(damaged).collect();
        let rises = frame.windows(2).filter(|w| !w[0] && w[1]).count() + frame[0] as usize;
        assert_eq!(rises, 3);
        assert_eq!(frame.iter().filter(|&&l| l).count(), 1800, "three flashes of 600 ms");
        assert!(frame[2600..].iter().all(|&l| !l), "2.4 s dark after the third");
        // every flash is longer than any fault's (150 ms) or blink's (500 ms)
        assert!(frame[..600].iter().all(|&l| l) && !frame[600]);
        // its steps land on the pattern's edges: the loop shows it exactly
        assert!((0..5000)
            .step_by(DAMAGED_STEP_MS as usize)
            .all(|t| { (t..t + DAMAGED_STEP_MS).all(|ms| damaged(ms) == damaged(t)) }));
    }

    #[test]
    fn a_refused_press_flickers_for_a_second_and_a_half_then_the_state_shows() {
        let at = 10_000;
        let seen = |from: u32, to: u32| (from..to).filter(|&ms| lit(State::Synced, true, ms, Some(at))).count();
        // flicker: half the time lit, distinct from every state's light
        assert_eq!(seen(at, at + REFUSED_MS), REFUSED_MS as usize / 2);
        // then synced's steady light again
        assert_eq!(seen(at + REFUSED_MS, at + 3_000), 1_500);
        // a refusal long ago (the clock wrapped since) shows nothing
        assert!(lit(State::Synced, true, 5, Some(u32::MAX - 10_000)));
    }
}
