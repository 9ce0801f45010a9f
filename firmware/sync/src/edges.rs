//! The lathe encoder's edge times: what the hardware latches, and where
//! an edge lies in count space.
//!
//! The board latches, at every rising edge of A, the count (TIM3_CCR1,
//! RM0383 §13.3.5) and the time (TIM5_CCR3 at 1 MHz, captured from TIM3's
//! compare pulse on TRGO: `firmware/src/edgetime.rs`). Only A's rising edge
//! is timed: A rises at the same place in every cycle of the disc, so the
//! interval between two such edges is free of the A/B duty-cycle and
//! quadrature errors that the other three edges carry.
//!
//! Where the edge lies is found without knowing whether the capture sees
//! the count before or after the same edge's count (the manual does not
//! say: the bench procedure checks it). Table 53 (§13.3.12) fixes the
//! cycle of states when counting up: (A,B) = (0,0) → (1,0) → (1,1) →
//! (0,1). With k0 the count in state (0,0), A rises between k0 and k0+1
//! counting up, and between k0+3 and k0+2 counting down. Whichever side
//! the capture takes, CCR1 − k0 is even exactly when the boundary is half
//! a count above it, and odd when it is half a count below: so the parity
//! of k0, read once at start, places every edge.

/// The last timed edge as the hardware latched it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeRegs {
    /// TIM3_CCR1: the count latched at A's rising edge
    pub count: u16,
    /// TIM5_CCR3: the edge's time, in stamps (1 µs), wrapping at 2^16
    pub stamp: u16,
}

/// How the stamps line up with the ticks and the counts with A and B,
/// measured once when the tick starts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeClock {
    /// the stamp at the instant of the first tick the core runs after
    /// `Controller::start_edges`: a tick's instant is its timer's update
    pub first_instant: u16,
    /// stamps per tick (50 at 1 MHz and 20 kHz): a whole number, so every
    /// instant falls on a stamp
    pub stamps_per_tick: u16,
    /// the parity of the count in state (A,B) = (0,0)
    pub low_low_odd: bool,
}

impl EdgeClock {
    /// The parity of k0 from a count and the A and B levels read with it
    /// (the lathe at rest, or two equal counts around the pin read).
    pub fn low_low_odd(count: u16, a: bool, b: bool) -> bool {
        // the state's place in the up-counting cycle of Table 53
        let place = match (a, b) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        (count.wrapping_sub(place) & 1) == 1
    }
}

/// Q8 stamps in 24 bits: the wrap of a tick's instant and of an edge's
/// stamp, which the timer and the track both mask with.
const WRAP_Q8: u32 = 0xFF_FFFF;

/// The edge's place in count space, in half counts (2·boundary), from the
/// 64-bit count the capture latched.
#[inline]
pub fn boundary_half_counts(count: i64, low_low_odd: bool) -> i64 {
    let even = ((count ^ low_low_odd as i64) & 1) == 0;
    2 * count + if even { 1 } else { -1 }
}

mod timer;
mod track;
pub use timer::EdgeTimer;

#[cfg(test)]
mod tests {
    use super::*;

    /// Walks the cycle of Table 53 up and down, with the capture taking
    /// either side of its own edge's count: the boundary found is the one
    /// between the two counts A rose between.
    #[test]
    fn every_a_rise_is_placed_on_its_boundary_whichever_count_the_capture_takes() {
        for k0 in [0i64, 1, 2, 3, 6, 7, 101] {
            let odd = k0 & 1 == 1;
            for cycle in [-3i64, 0, 5] {
                let base = k0 + 4 * cycle;
                // up: A rises between base and base+1 (boundary base+½)
                assert_eq!(boundary_half_counts(base, odd), 2 * base + 1);
                assert_eq!(boundary_half_counts(base + 1, odd), 2 * base + 1);
                // down: A rises between base+3 and base+2 (boundary base+2½)
                assert_eq!(boundary_half_counts(base + 3, odd), 2 * base + 5);
                assert_eq!(boundary_half_counts(base + 2, odd), 2 * base + 5);
            }
        }
    }

    #[test]
    fn the_parity_follows_the_state_read_with_the_count() {
        // k0 = 10: counts 10, 11, 12, 13 are (0,0), (1,0), (1,1), (0,1)
        assert!(!EdgeClock::low_low_odd(10, false, false));
        assert!(!EdgeClock::low_low_odd(11, true, false));
        assert!(!EdgeClock::low_low_odd(12, true, true));
        assert!(!EdgeClock::low_low_odd(13, false, true));
        assert!(EdgeClock::low_low_odd(14, true, false));
        assert!(EdgeClock::low_low_odd(0, false, true));
    }
}
