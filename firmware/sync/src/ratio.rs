//! An exact gear ratio GR = p/q between the cutter and the lathe.
//!
//! Foale ("Turning polygons on a lathe", 2022: "five basic variables", item
//! 2) and Ghionea et al. (eq. 1: i = n_T/n_p = z_p/z_T) both define the ratio as cutter turns per
//! lathe turn. It may be fractional: the work gets N = numerator(GR·Z) flats.

/// Largest numerator or denominator accepted after reduction.
pub const RATIO_MAX_TERM: u32 = 1000;

use crate::console::number::digits;

/// A reduced, positive rational with both terms in 1..=[`RATIO_MAX_TERM`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ratio {
    num: u16,
    den: u16,
}

/// Why a ratio was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RatioError {
    /// Not an integer, `p/q`, `p:q` or a plain decimal.
    Syntax,
    /// Zero or negative.
    NotPositive,
    /// A zero denominator.
    ZeroDenominator,
    /// A term is above [`RATIO_MAX_TERM`] after reduction.
    TooLarge,
}

impl RatioError {
    /// One line for a machinist: what was wrong and what is allowed.
    pub fn describe(self) -> &'static str {
        match self {
            RatioError::Syntax => "must be an integer, p/q, p:q or a decimal like 2.5 (up to 6 decimals)",
            RatioError::NotPositive => "must be greater than 0",
            RatioError::ZeroDenominator => "has a zero denominator",
            RatioError::TooLarge => "needs numerator and denominator in 1..=1000 after reduction",
        }
    }
}

/// Greatest common divisor (Euclid), shared by the core and the host tools.
pub const fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        let t = a % b;
        a = b;
        b = t;
    }
    a
}

impl Ratio {
    /// 2:1, the default (Foale's "nearly magic" ratio).
    pub const TWO: Ratio = Ratio { num: 2, den: 1 };

    /// Builds p/q, reducing it first.
    pub fn new(p: u64, q: u64) -> Result<Ratio, RatioError> {
        if q == 0 {
            return Err(RatioError::ZeroDenominator);
        }
        if p == 0 {
            return Err(RatioError::NotPositive);
        }
        let g = gcd(p, q);
        let (p, q) = (p / g, q / g);
        if p > RATIO_MAX_TERM as u64 || q > RATIO_MAX_TERM as u64 {
            return Err(RatioError::TooLarge);
        }
        Ok(Ratio { num: p as u16, den: q as u16 })
    }

    /// Parses `2`, `11/3`, `11:3` or `2.5` (an exact decimal: 2.5 = 5/2).
    /// `p:q` is the shop's way of writing p/q (`2:1`); a second
    /// separator of either kind lands in a term, which refuses it.
    pub fn parse(text: &str) -> Result<Ratio, RatioError> {
        let text = text.trim();
        if text.starts_with('-') {
            return Err(RatioError::NotPositive);
        }
        if let Some((p, q)) = text.split_once(['/', ':']) {
            return Ratio::new(parse_uint(p)?, parse_uint(q)?);
        }
        match text.split_once('.') {
            Some((whole, frac)) => parse_decimal(whole, frac),
            None => Ratio::new(parse_uint(text)?, 1),
        }
    }

    pub const fn num(self) -> u32 {
        self.num as u32
    }

    pub const fn den(self) -> u32 {
        self.den as u32
    }

    /// The cutter's flats count and pattern period for `edges` evenly spaced
    /// edges: GR·Z = N/r in lowest terms, N flats cut over r lathe turns.
    pub fn pattern(self, edges: u32) -> (u32, u32) {
        let pz = self.num() as u64 * edges as u64;
        let g = gcd(pz, self.den() as u64).max(1);
        ((pz / g) as u32, (self.den() as u64 / g) as u32)
    }

    /// Approximate value, for planning and display only.
    pub fn to_f64(self) -> f64 {
        self.num() as f64 / self.den() as f64
    }
}

/// A term as the console's other numbers are written (`console::number`):
/// no sign, no leading zero. A whole number past 64 bits is one too large,
/// not one mistyped.
fn parse_uint(s: &str) -> Result<u64, RatioError> {
    let s = s.trim();
    match digits(s) {
        Some(d) => d.parse::<u64>().map_err(|_| RatioError::TooLarge),
        None if s.starts_with('-') => Err(RatioError::NotPositive),
        None => Err(RatioError::Syntax),
    }
}

/// `whole.frac` is whole + frac/10^len exactly; at most 6 decimals (digits,
/// their leading zeros included: `2.05`), and a whole part (`0.5`, not `.5`).
fn parse_decimal(whole: &str, frac: &str) -> Result<Ratio, RatioError> {
    if frac.is_empty() || frac.len() > 6 || !frac.bytes().all(|b| b.is_ascii_digit()) {
        return Err(RatioError::Syntax);
    }
    let w = parse_uint(whole)?;
    let f = frac.bytes().fold(0, |f, b| f * 10 + u64::from(b - b'0'));
    let scale = 10u64.pow(frac.len() as u32);
    let num = w.checked_mul(scale).and_then(|n| n.checked_add(f)).ok_or(RatioError::TooLarge)?;
    Ratio::new(num, scale)
}

impl core::fmt::Display for Ratio {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.den == 1 {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

#[cfg(test)]
mod limits_tests;

#[cfg(test)]
mod notation_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_documents_examples_reduced() {
        assert_eq!(Ratio::parse("2").unwrap(), Ratio::new(2, 1).unwrap());
        assert_eq!(Ratio::parse("2.5").unwrap(), Ratio::new(5, 2).unwrap());
        assert_eq!(Ratio::parse("22/6").unwrap(), Ratio::new(11, 3).unwrap());
        assert_eq!(Ratio::parse("1.25").unwrap().den(), 4);
    }

    #[test]
    fn refuses_bad_ratios_with_a_reason() {
        assert_eq!(Ratio::parse("0"), Err(RatioError::NotPositive));
        assert_eq!(Ratio::parse("-2"), Err(RatioError::NotPositive));
        // a negative term after the separator is not positive either, not a syntax error
        assert_eq!(Ratio::parse("2/-1"), Err(RatioError::NotPositive));
        assert_eq!(Ratio::parse("2:-3"), Err(RatioError::NotPositive));
        assert_eq!(Ratio::parse("3/ -2"), Err(RatioError::NotPositive));
        assert_eq!(Ratio::parse("1/0"), Err(RatioError::ZeroDenominator));
        assert_eq!(Ratio::parse("abc"), Err(RatioError::Syntax));
        assert_eq!(Ratio::parse("NaN"), Err(RatioError::Syntax));
        assert_eq!(Ratio::parse("1001"), Err(RatioError::TooLarge));
        assert_eq!(Ratio::parse("1/1001"), Err(RatioError::TooLarge));
        assert_eq!(Ratio::parse("2000/2").unwrap().num(), 1000);
    }

    #[test]
    fn flats_and_period_follow_the_reduced_product() {
        let r = |s| Ratio::parse(s).unwrap();
        assert_eq!(r("5/2").pattern(2), (5, 1));
        assert_eq!(r("4/3").pattern(3), (4, 1));
        assert_eq!(r("11/3").pattern(3), (11, 1));
        assert_eq!(r("11/3").pattern(1), (11, 3));
        assert_eq!(r("2").pattern(3), (6, 1));
    }
}
