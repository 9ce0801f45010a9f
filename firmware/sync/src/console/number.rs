//! The console's numbers, in the one syntax the help and the README give:
//! ASCII digits with no sign and no leading zero (`0`
//! itself is fine), a `-` before them for a signed value, hex digits for a
//! checksum. Rust's own parsers also take `+5` and `00004`, which no
//! document shows: every field parses its numbers here instead.

/// `0`, `5`, `1000`; None for a sign, a leading zero, anything but
/// digits, or more than `u32::MAX`.
pub fn unsigned(s: &str) -> Option<u32> {
    digits(s)?.parse().ok()
}

/// `s` if it is an unsigned number's text (any length): the ratio's terms
/// read it into 64 bits.
pub fn digits(s: &str) -> Option<&str> {
    let b = s.as_bytes();
    let leading_zero = b.len() > 1 && b[0] == b'0';
    (!b.is_empty() && !leading_zero && b.iter().all(u8::is_ascii_digit)).then_some(s)
}

/// `unsigned`, or `-` and `unsigned`, within `i32` (`-0` is 0).
pub fn signed(s: &str) -> Option<i32> {
    match s.strip_prefix('-') {
        Some(magnitude) => i32::try_from(-i64::from(unsigned(magnitude)?)).ok(),
        None => i32::try_from(unsigned(s)?).ok(),
    }
}

/// 1 to 8 hex digits, no sign: a CRC-32 as `{:08x}` writes it (its
/// leading zeros are digits of the checksum, not padding to refuse).
pub fn hex32(s: &str) -> Option<u32> {
    if s.is_empty() || s.len() > 8 || !s.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(s, 16).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unsigned_number_is_digits_without_sign_or_leading_zero() {
        assert_eq!(unsigned("0"), Some(0));
        assert_eq!(unsigned("5"), Some(5));
        assert_eq!(unsigned("1000"), Some(1000));
        assert_eq!(unsigned("10"), Some(10), "a zero that is not leading");
        assert_eq!(unsigned("4294967295"), Some(u32::MAX));
        assert_eq!(digits("40000000000000"), Some("40000000000000"), "any length: the caller bounds it");
        assert_eq!(digits("040"), None);
        assert_eq!(digits(""), None);
        for bad in ["", "+5", "-5", "00004", "00", "05", "4294967296", "1e3", "5 ", " 5", "0x10", "٣"] {
            assert_eq!(unsigned(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn a_signed_number_is_an_unsigned_one_with_an_optional_minus() {
        assert_eq!(signed("0"), Some(0));
        assert_eq!(signed("-0"), Some(0));
        assert_eq!(signed("-7"), Some(-7));
        assert_eq!(signed("7"), Some(7));
        assert_eq!(signed("2147483647"), Some(i32::MAX));
        assert_eq!(signed("-2147483648"), Some(i32::MIN));
        for bad in ["2147483648", "-2147483649", "+7", "--7", "-", "-07", "- 7", "", "-+7"] {
            assert_eq!(signed(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn a_checksum_is_one_to_eight_hex_digits_without_sign() {
        assert_eq!(hex32("0"), Some(0));
        assert_eq!(hex32("00ab12cd"), Some(0x00ab_12cd));
        assert_eq!(hex32("FFFFFFFF"), Some(u32::MAX));
        assert_eq!(hex32("a"), Some(10));
        for bad in ["", "+abc", "-1", "1ffffffff", "000000000", "0x1f", "g"] {
            assert_eq!(hex32(bad), None, "{bad:?}");
        }
    }
}
