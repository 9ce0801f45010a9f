//! The independent watchdog's real period. embassy-stm32 0.6 computes the
//! prescaler and reload for an LSI of 32 kHz (`wdg/mod.rs`: the smallest
//! prescaler 4..256 whose full count reaches the timeout, then the reload
//! for it); the F411's LSI is 17 to 47 kHz (DS10314, "LSI oscillator
//! characteristics"), so the period the silicon keeps spans that range.

/// The watchdog's period as asked of embassy (at its 32 kHz assumption).
pub const WATCHDOG_US: u32 = 8_000_000;
/// The LSI's range, DS10314.
pub const LSI_MIN_HZ: u32 = 17_000;
pub const LSI_MAX_HZ: u32 = 47_000;
/// embassy's assumption (`rcc::LSI_FREQ`).
const EMBASSY_LSI_HZ: u32 = 32_000;
const MAX_RL: u32 = 0xFFF;

/// (prescaler, reload) as embassy writes them for `timeout_us`.
pub fn embassy_setting(timeout_us: u32) -> (u32, u32) {
    let full = |psc: u32| (1_000_000u64 * (MAX_RL as u64 + 1) * psc as u64 / EMBASSY_LSI_HZ as u64) as u32;
    let psc = (2..=8).map(|p| 1u32 << p).find(|&psc| timeout_us <= full(psc)).unwrap_or(256);
    let rl = (timeout_us / psc * EMBASSY_LSI_HZ / 1_000_000).saturating_sub(1);
    (psc, rl)
}

/// The period in µs with an LSI of `lsi_hz` (RM0383 §15.3: the counter
/// counts down from the reload at LSI / prescaler).
pub fn period_us(timeout_us: u32, lsi_hz: u32) -> u32 {
    let (psc, rl) = embassy_setting(timeout_us);
    ((rl as u64 + 1) * psc as u64 * 1_000_000 / lsi_hz as u64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embassy_chooses_prescaler_64_reload_3999_for_8_s() {
        // embassy's own test: get_timeout_us(64, 3999) == 8_000_000
        assert_eq!(embassy_setting(WATCHDOG_US), (64, 3999));
        assert_eq!(period_us(WATCHDOG_US, EMBASSY_LSI_HZ), 8_000_000);
    }

    #[test]
    fn the_real_period_spans_5_4_to_15_s_over_the_lsi_range() {
        assert_eq!(period_us(WATCHDOG_US, LSI_MAX_HZ), 5_446_808);
        assert_eq!(period_us(WATCHDOG_US, LSI_MIN_HZ), 15_058_823);
    }
}
