//! The parser's limits: terms within 64 bits (a longer one, or a decimal
//! whose scaled value is not, is too large), at most 6 decimals, and the
//! value shown back.

use super::*;

#[test]
fn terms_of_twelve_digits_are_read_and_reduced() {
    assert_eq!(Ratio::parse("999999999999/999999999999"), Ok(Ratio::new(1, 1).unwrap()));
    assert_eq!(Ratio::parse("200000000000/100000000000"), Ok(Ratio::TWO));
    assert_eq!(Ratio::parse("100000000000/300000000000"), Ok(Ratio::new(1, 3).unwrap()));
}

#[test]
fn long_terms_are_reduced_and_past_64_bits_are_too_large() {
    // valid after reduction, however long
    assert_eq!(Ratio::parse("1000000000000/1000000000000"), Ok(Ratio::new(1, 1).unwrap()));
    assert_eq!(Ratio::parse("3/1000000000000"), Err(RatioError::TooLarge));
    assert_eq!(Ratio::parse("1000000000000000000"), Err(RatioError::TooLarge));
    // 19 digits fit a u64, but times 10^6 for the decimals they would not
    assert_eq!(Ratio::parse("1000000000000000000.5"), Err(RatioError::TooLarge));
    assert_eq!(Ratio::parse("9999999999999999999.999999"), Err(RatioError::TooLarge));
    assert_eq!(Ratio::parse("1.5/1"), Err(RatioError::Syntax));
}

#[test]
fn up_to_six_decimals_are_exact_and_a_seventh_is_refused() {
    assert_eq!(Ratio::parse("2.500000"), Ok(Ratio::new(5, 2).unwrap()));
    assert_eq!(Ratio::parse("0.125000"), Ok(Ratio::new(1, 8).unwrap()));
    // six decimals are read: 1000001/1000000 is then too fine a ratio
    assert_eq!(Ratio::parse("1.000001"), Err(RatioError::TooLarge));
    assert_eq!(Ratio::parse("0.003"), Ok(Ratio::new(3, 1000).unwrap()));
    assert_eq!(Ratio::parse("12.125"), Ok(Ratio::new(97, 8).unwrap()));
    assert_eq!(Ratio::parse("2.5000000"), Err(RatioError::Syntax), "seven decimals");
    assert_eq!(Ratio::parse("2."), Err(RatioError::Syntax));
    assert_eq!(Ratio::parse(".5"), Err(RatioError::Syntax), "the documents write 0.5");
    assert_eq!(Ratio::parse("2.05"), Ok(Ratio::new(41, 20).unwrap()), "a decimal's leading zero is a digit");
    assert_eq!(Ratio::parse("2.5a"), Err(RatioError::Syntax));
}

#[test]
fn a_ratio_shows_as_its_reduced_terms() {
    let show = |s: &str| std::format!("{}", Ratio::parse(s).unwrap());
    assert_eq!(show("4/2"), "2");
    assert_eq!(show("22/6"), "11/3");
    assert_eq!(show("0.5"), "1/2");
    assert_eq!(Ratio::parse("11/3").unwrap().to_f64(), 11.0 / 3.0);
    assert_eq!(Ratio::TWO.to_f64(), 2.0);
}

#[test]
fn gcd_is_euclids() {
    assert_eq!(gcd(12, 18), 6);
    assert_eq!(gcd(18, 12), 6);
    assert_eq!(gcd(7, 0), 7);
    assert_eq!(gcd(17, 5), 1);
    assert_eq!(gcd(6400, 2400), 800);
}

#[test]
fn a_term_is_written_as_the_documents_write_it_without_sign_or_leading_zero() {
    for bad in ["+5", "02", "2/03", "+11/3", "11/+3", "02.5", "00.5", "2.+5", "2.-5"] {
        assert_eq!(Ratio::parse(bad), Err(RatioError::Syntax), "{bad}");
    }
    assert_eq!(Ratio::parse("-02"), Err(RatioError::NotPositive));
    assert_eq!(Ratio::parse("10/20"), Ok(Ratio::new(1, 2).unwrap()), "zeros that are not leading");
    assert_eq!(Ratio::parse("0.5"), Ok(Ratio::new(1, 2).unwrap()));
}
