//! A `set` that does not fit with the others, said with the bound of the
//! setting being set given the others' values (`config::together`): worked
//! out here, when the reply is written, in whole numbers.

use super::{named, Reply};
use crate::config::together::Bound;
use crate::config::Misfit;
use crate::ratio::{gcd, RATIO_MAX_TERM};
use core::fmt::Write;

/// `error: ratio must be at most 5/2 with max-rpm 1500, steps 3200 and
/// max-rate 200000 (the rule)`; for a setting that is no number of the
/// rule (`drive`, `bldc-out`), the rule and the values of its settings.
pub(super) fn write(m: &Misfit, out: &mut Reply) {
    let _ = write!(out, "error: {} ", m.setting);
    match m.bound() {
        Some(b) => {
            let _ = out.push_str(if b.at_most { "must be at most " } else { "must be at least " });
            write_bound(m.setting, b, out);
            write_values(m, Some(m.setting), out);
            let _ = write!(out, " ({})", m.rule.formula());
        }
        None => {
            let _ = write!(out, "does not fit with the others: {} (", m.rule.formula());
            write_values(m, None, out);
            let _ = out.push(')');
        }
    }
}

/// A whole-number setting's bound rounded inwards (the largest or least
/// value that fits), the ratio's as a ratio the console takes where it is
/// one (`5/2`), else as a decimal.
fn write_bound(setting: &str, b: Bound, out: &mut Reply) {
    let _ = match setting {
        "ratio" => write_ratio(b.num, b.den, out),
        _ if b.at_most => write!(out, "{}", b.num / b.den),
        _ => write!(out, "{}", b.num.div_ceil(b.den)),
    };
}

/// `n/d` reduced, or, where its terms are past what `set ratio` takes, as
/// a decimal: `2.501`, or 4 decimals rounded down and `...` if more follow.
fn write_ratio(n: u64, d: u64, out: &mut Reply) -> core::fmt::Result {
    let g = gcd(n, d);
    let (n, d) = (n / g, d / g);
    if d == 1 {
        return write!(out, "{n}");
    }
    if n <= RATIO_MAX_TERM as u64 && d <= RATIO_MAX_TERM as u64 {
        return write!(out, "{n}/{d}");
    }
    write!(out, "{}.", n / d)?;
    let mut rest = n % d;
    for _ in 0..4 {
        if rest == 0 {
            return Ok(());
        }
        write!(out, "{}", rest * 10 / d)?;
        rest = rest * 10 % d;
    }
    if rest != 0 {
        out.push_str("...").map_err(|_| core::fmt::Error)?;
    }
    Ok(())
}

/// ` with a 1, b 2 and c 3`: the rule's settings but `skip`, as the board
/// holds them (the one being set, if listed, as given).
fn write_values(m: &Misfit, skip: Option<&str>, out: &mut Reply) {
    let c = &m.config;
    let mut names = m.rule.settings(c).iter().copied().filter(|n| Some(*n) != skip).peekable();
    let mut first = true;
    while let Some(name) = names.next() {
        let _ = out.push_str(match (first, names.peek()) {
            (true, _) if skip.is_some() => " with ",
            (true, _) => "with ",
            (false, Some(_)) => ", ",
            (false, None) => " and ",
        });
        named(c, name, ' ', out);
        first = false;
    }
}

#[cfg(test)]
#[path = "misfit_tests.rs"]
mod tests;
