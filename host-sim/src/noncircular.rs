//! Noncircular turning with sharp corners (Theorem 2 of the noncircular
//! turning note, "Noncircular Turning of Workpieces With Sharp Corners"): a polygon's
//! N sides are cut in m workpiece revolutions in the order i·m mod N, with
//! m > 1 co-prime with N. After cutting side k the tool reaches corner
//! k|k+1; the next cut, side k+m, never starts there (m ≢ 1 mod N), so each
//! sharp corner is made by two different smooth passes, with a smooth
//! non-cutting link between cuts.

use polyturn_sync::ratio::gcd;

pub mod path;
#[cfg(test)]
mod path_tests;
pub mod plan;
pub mod rounded;
pub mod table;

/// Why a cutting sequence was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SequenceError {
    TooFewSides,
    MTooSmall,
    SharesFactor(u32),
    Adjacent,
}

impl SequenceError {
    pub fn describe(&self) -> String {
        match self {
            SequenceError::TooFewSides => "a polygon has at least 3 sides".into(),
            SequenceError::MTooSmall => {
                "must be greater than 1 (m = 1 cuts the sides in turn, each corner in one pass)".into()
            }
            SequenceError::SharesFactor(g) => {
                format!("shares the factor {g} with the number of sides: it must be co-prime with N")
            }
            SequenceError::Adjacent => {
                "is 1 modulo N: each side would be cut straight after the one before, turning every corner in one pass"
                    .into()
            }
        }
    }
}

/// Checks m for N sides.
pub fn check(sides: u32, m: u32) -> Result<(), SequenceError> {
    if sides < 3 {
        return Err(SequenceError::TooFewSides);
    }
    if m < 2 {
        return Err(SequenceError::MTooSmall);
    }
    let g = gcd(sides as u64, m as u64) as u32;
    if g != 1 {
        return Err(SequenceError::SharesFactor(g));
    }
    if m % sides == 1 {
        return Err(SequenceError::Adjacent);
    }
    Ok(())
}

/// The smallest valid m (Theorem 2: the fewest revolutions).
pub fn smallest_m(sides: u32) -> Result<u32, SequenceError> {
    if sides < 3 {
        return Err(SequenceError::TooFewSides);
    }
    (2..=sides).find(|&m| check(sides, m).is_ok()).ok_or(SequenceError::TooFewSides)
}

/// The sides in cutting order: i·m mod N for i = 0..N.
pub fn order(sides: u32, m: u32) -> Vec<u32> {
    (0..sides as u64).map(|i| ((i * m as u64) % sides as u64) as u32).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_papers_octagon_example() {
        assert_eq!(smallest_m(8), Ok(3));
        assert_eq!(order(8, 3), vec![0, 3, 6, 1, 4, 7, 2, 5]);
    }

    #[test]
    fn odd_sides_take_m_2_and_six_and_twelve_take_5() {
        for n in (3..60).step_by(2) {
            assert_eq!(smallest_m(n), Ok(2), "N = {n}");
        }
        assert_eq!(smallest_m(6), Ok(5));
        assert_eq!(smallest_m(12), Ok(5));
    }

    #[test]
    fn every_order_covers_each_side_once_and_never_cuts_the_next_side_in_turn() {
        for n in 3..200 {
            let m = smallest_m(n).unwrap();
            let o = order(n, m);
            let mut seen = o.clone();
            seen.sort();
            assert_eq!(seen, (0..n).collect::<Vec<_>>(), "N = {n}");
            for k in 0..o.len() {
                let (a, b) = (o[k], o[(k + 1) % o.len()]);
                // side b must not start at the corner where side a ended
                assert_ne!((b + n - a) % n, 1, "N = {n}, m = {m}: {a} then {b}");
            }
        }
    }

    #[test]
    fn invalid_m_is_refused_with_the_reason() {
        assert_eq!(check(8, 2), Err(SequenceError::SharesFactor(2)));
        assert_eq!(check(8, 9), Err(SequenceError::Adjacent));
        assert_eq!(check(8, 7), Ok(()));
        assert_eq!(check(8, 1), Err(SequenceError::MTooSmall));
        assert_eq!(check(2, 3), Err(SequenceError::TooFewSides));
        assert!(SequenceError::SharesFactor(2).describe().contains("co-prime"));
    }
}
