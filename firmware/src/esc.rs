//! BLDC speed command → ESC servo pulse: 1000 µs stop … 2000 µs full speed
//! (the usual RC ESC range), for a unidirectional ESC: the motor is wired to
//! turn the way the gear turns it (`dir`), and a command the other way (the
//! phase loop asking it to slow past zero) can only be the stop pulse: as a
//! throttle it would drive the motor forward, the wrong way for the loop.

/// The pulse that stops an RC ESC.
pub const STOP_US: u16 = 1000;

/// The ESC pulse for this tick: a speed only while a BLDC drive is enabled
/// and nothing halts it; every fault, E-stop, alarm or other drive gets the
/// stop pulse. `forward`: the motor's wired sense is the core's positive one
/// (`dir same`); a speed of the other sign gets the stop pulse.
pub fn command(bldc: bool, enable: bool, halt: bool, speed_q16: i32, max_q16: i64, forward: bool) -> u16 {
    let wired = if forward { speed_q16 > 0 } else { speed_q16 < 0 };
    if bldc && enable && !halt && wired {
        pulse_us(speed_q16, max_q16)
    } else {
        STOP_US
    }
}

/// `speed_q16` and `max_q16` as the core gives them (Q16 counts per tick).
/// In 32 bits (no 64-bit division in the tick): `max-rate` ≤ 250 kHz at
/// 25 kHz keeps `max_q16` ≤ 655 360, so `frac × 1000` < 2^32.
pub fn pulse_us(speed_q16: i32, max_q16: i64) -> u16 {
    if max_q16 <= 0 {
        return STOP_US;
    }
    let max = max_q16.min(4_000_000) as u32;
    let frac = speed_q16.unsigned_abs().min(max);
    STOP_US + (frac * 1000 / max) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stop_half_and_full_and_never_beyond() {
        assert_eq!(pulse_us(0, 1000), 1000);
        assert_eq!(pulse_us(500, 1000), 1500);
        assert_eq!(pulse_us(5000, 1000), 2000);
        assert_eq!(pulse_us(-500, 1000), 1500);
        assert_eq!(pulse_us(10, 0), 1000);
        // the largest the settings allow: 250 kHz at 25 kHz, Q16
        assert_eq!(pulse_us(655_360, 655_360), 2000);
        assert_eq!(pulse_us(327_680, 655_360), 1500);
    }

    #[test]
    fn anything_but_an_enabled_running_bldc_gets_the_stop_pulse() {
        assert_eq!(command(true, true, false, 500, 1000, true), 1500);
        assert_eq!(command(true, true, true, 500, 1000, true), STOP_US, "halt (E-stop, alarm)");
        assert_eq!(command(true, false, false, 500, 1000, true), STOP_US, "disabled (fault, idle)");
        assert_eq!(command(false, true, false, 500, 1000, true), STOP_US, "another drive");
    }

    #[test]
    fn a_speed_against_the_wired_sense_is_the_stop_pulse_never_a_throttle() {
        // dir same: forward is positive; dir opposite: negative
        assert_eq!(command(true, true, false, -500, 1000, true), STOP_US);
        assert_eq!(command(true, true, false, -500, 1000, false), 1500);
        assert_eq!(command(true, true, false, 500, 1000, false), STOP_US);
        assert_eq!(command(true, true, false, 0, 1000, true), STOP_US);
    }
}
