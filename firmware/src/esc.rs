//! BLDC speed command → ESC servo pulse: 1000 µs stop … 2000 µs full speed
//! (the usual RC ESC range), for a unidirectional ESC.

/// `speed_q16` and `max_q16` as the core gives them (Q16 counts per tick).
pub fn pulse_us(speed_q16: i32, max_q16: i64) -> u16 {
    if max_q16 <= 0 {
        return 1000;
    }
    let frac = (speed_q16.unsigned_abs() as i64).min(max_q16);
    (1000 + frac * 1000 / max_q16) as u16
}

#[cfg(test)]
mod tests {
    #[test]
    fn stop_half_and_full_and_never_beyond() {
        assert_eq!(super::pulse_us(0, 1000), 1000);
        assert_eq!(super::pulse_us(500, 1000), 1500);
        assert_eq!(super::pulse_us(5000, 1000), 2000);
        assert_eq!(super::pulse_us(-500, 1000), 1500);
        assert_eq!(super::pulse_us(10, 0), 1000);
    }
}
