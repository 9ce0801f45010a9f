//! The shop's notation: `2:1` and `11:3` are the same ratios as
//! `2/1` and `11/3`, and `:` is refused wherever `/` is.

use super::*;

#[test]
fn a_colon_separates_the_terms_as_a_slash_does() {
    assert_eq!(Ratio::parse("2:1"), Ok(Ratio::TWO));
    assert_eq!(Ratio::parse("11:3"), Ok(Ratio::new(11, 3).unwrap()));
    assert_eq!(Ratio::parse("22:6"), Ok(Ratio::new(11, 3).unwrap()), "reduced like 22/6");
    assert_eq!(Ratio::parse(" 5:2 "), Ratio::parse("5/2"), "trimmed alike");
    assert_eq!(Ratio::parse("1:1000"), Ok(Ratio::new(1, 1000).unwrap()));
}

#[test]
fn a_colon_ratio_is_shown_back_with_a_slash_as_before() {
    let show = |s: &str| std::format!("{}", Ratio::parse(s).unwrap());
    assert_eq!(show("2:1"), "2");
    assert_eq!(show("11:3"), "11/3");
}

#[test]
fn a_colon_ratio_is_refused_for_the_same_reasons_as_a_slash_ratio() {
    for (colon, slash) in [
        ("1:0", "1/0"),
        ("0:1", "0/1"),
        ("1:1001", "1/1001"),
        ("2:03", "2/03"),
        ("2:-1", "2/-1"),
        ("1.5:1", "1.5/1"),
        ("2:", "2/"),
        (":2", "/2"),
        ("1000000000000:1", "1000000000000/1"),
    ] {
        assert_eq!(Ratio::parse(colon), Ratio::parse(slash), "{colon} against {slash}");
        assert!(Ratio::parse(colon).is_err(), "{colon}");
    }
    assert_eq!(Ratio::parse("-2:1"), Err(RatioError::NotPositive));
    assert_eq!(Ratio::parse("1001:1"), Err(RatioError::TooLarge));
}

#[test]
fn one_separator_only_and_not_both() {
    for bad in ["2:1:1", "2:1/1", "2/1:1", "2/1/1", "2::1", "2;1", "2 : 1x"] {
        assert_eq!(Ratio::parse(bad), Err(RatioError::Syntax), "{bad}");
    }
}

#[test]
fn the_syntax_refusal_names_both_separators() {
    assert_eq!(RatioError::Syntax.describe(), "must be an integer, p/q, p:q or a decimal like 2.5 (up to 6 decimals)");
}

/// A whole number too large for any setting is told the range, however
/// many digits it has, not that it is no number; a decimal's too.
#[test]
fn a_huge_whole_number_is_told_the_range_not_the_syntax() {
    for huge in [
        "11111111111111111111111",
        "99999999999",
        "1000000000000:1",
        "3/18446744073709551616",
        "18446744073709551615.5",
    ] {
        assert_eq!(Ratio::parse(huge), Err(RatioError::TooLarge), "{huge}");
    }
    assert_eq!(Ratio::parse("2.5"), Ratio::new(5, 2));
}
