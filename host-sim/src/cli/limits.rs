//! How a limit is said: a top speed rounded down, so that the figure
//! named is one that is taken, and a figure needed against the limit it
//! passes with enough digits that the two read differently.

/// A lathe speed rounded down to a tenth of an rpm, as a limit must be
/// (28.75 is "28.7": 28.8 would exceed it). Never a figure that reads
/// back above `rpm` (28.7 x 10 may come out a hair over 287).
pub fn floor_tenth(rpm: f64) -> String {
    let mut tenths = (rpm * 10.0).floor();
    while tenths > 0.0 && format!("{:.1}", tenths / 10.0).parse::<f64>().is_ok_and(|v| v > rpm) {
        tenths -= 1.0;
    }
    format!("{:.1}", tenths / 10.0)
}

/// `need`, past `limit`, to `decimals` places, or as many as `limit` is
/// written with, or as many more as make it read differently from `limit`
/// at the same places (0.50012 against 0.5 is "0.5001", not "0.5"; 0.548
/// against 0.2 is "0.5", not "1").
pub fn past(need: f64, limit: f64, decimals: usize) -> String {
    let written = limit.to_string().split_once('.').map_or(0, |(_, f)| f.len());
    (decimals.max(written)..=12)
        .map(|d| (format!("{need:.d$}"), format!("{limit:.d$}")))
        .find(|(n, l)| n != l)
        .map_or_else(|| need.to_string(), |(n, _)| n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_speed_limit_is_rounded_down_to_a_figure_within_it() {
        assert_eq!(floor_tenth(28.75), "28.7");
        assert_eq!(floor_tenth(2.69999), "2.6");
        assert_eq!(floor_tenth(2.7), "2.7");
        assert_eq!(floor_tenth(95.49), "95.4");
    }

    #[test]
    fn a_need_reads_differently_from_the_limit_it_passes() {
        assert_eq!(past(0.50012, 0.5, 0), "0.5001");
        assert_eq!(past(100.4, 100.0, 0), "100.4");
        assert_eq!(past(241.876, 12.0, 2), "241.88");
        assert_eq!(past(0.548, 0.2, 0), "0.5");
    }
}
