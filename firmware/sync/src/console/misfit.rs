//! A `set` that does not fit with the others, said with the bound of the
//! setting being set given the others' values (`config::together`): worked
//! out here, when the reply is written, in whole numbers.

use super::{named, Reply};
use crate::config::together::Bound;
use crate::config::Misfit;
use crate::ratio::RATIO_MAX_TERM;
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
/// value that fits), the ratio's (always an upper one: `Rule::bound`) as
/// the largest ratio the console takes within it: what can be typed.
fn write_bound(setting: &str, b: Bound, out: &mut Reply) {
    let _ = match setting {
        "ratio" => write_ratio(b.num, b.den, out),
        _ if b.at_most => write!(out, "{}", b.num / b.den),
        _ => write!(out, "{}", b.num.div_ceil(b.den)),
    };
}

/// The largest ratio `set ratio` takes (terms at most 1000) at or below
/// `n/d`: `5/2`, `998/333`; as a decimal if even 1/1000 is above it.
fn write_ratio(n: u64, d: u64, out: &mut Reply) -> core::fmt::Result {
    match largest_at_most(n, d) {
        Some((p, 1)) => write!(out, "{p}"),
        Some((p, q)) => write!(out, "{p}/{q}"),
        None => write_decimal(n, d, out),
    }
}

/// The largest p/q ≤ n/d with 1 ≤ p, q ≤ 1000, in lowest terms (the first
/// denominator to reach a value is its least): for each denominator the
/// largest numerator that fits. In the reply's writing, outside the tick's
/// lock.
fn largest_at_most(n: u64, d: u64) -> Option<(u64, u64)> {
    let most = RATIO_MAX_TERM as u64;
    let mut best: Option<(u64, u64)> = None;
    for q in 1..=most {
        let p = (n as u128 * q as u128 / d.max(1) as u128).min(most as u128) as u64;
        if p > 0 && best.is_none_or(|(bp, bq)| p * bq > bp * q) {
            best = Some((p, q));
        }
    }
    best
}

/// `n/d` as a decimal: `0.0005`, or 4 decimals rounded down and `...` if
/// more follow.
fn write_decimal(n: u64, d: u64, out: &mut Reply) -> core::fmt::Result {
    let d = d.max(1);
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
