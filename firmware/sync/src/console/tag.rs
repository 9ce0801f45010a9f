//! Reply tags: a program that talks to the console puts `#N ` (1 to 6
//! digits) before a command, and the reply comes back as `#N ok ...` or
//! `#N error: ...`. `watch`'s status lines carry no tag, so a reply can
//! never be mistaken for a stale status line (or a status line for a
//! reply), and a reply to an earlier command can never be taken for the
//! answer to a later one. A person at a terminal sends no tag and gets
//! none back.

/// The most digits a tag may have (keeps a tagged cam line within the
/// firmware's 96-byte line).
pub const TAG_DIGITS: usize = 6;

/// `#42 status` → `(Some(b"42"), b"status")`; an untagged line is
/// returned whole. A malformed tag is refused.
pub fn split(line: &[u8]) -> Result<(Option<&[u8]>, &[u8]), &'static str> {
    let Some(rest) = line.strip_prefix(b"#") else { return Ok((None, line)) };
    let end = rest.iter().position(|&b| b == b' ').unwrap_or(rest.len());
    let (tag, body) = rest.split_at(end);
    if tag.is_empty() || tag.len() > TAG_DIGITS || !tag.iter().all(u8::is_ascii_digit) {
        return Err("a tag is # and 1 to 6 digits, then a space and the command");
    }
    Ok((Some(tag), body.strip_prefix(b" ").unwrap_or(body)))
}

#[cfg(test)]
mod tests {
    use super::split;

    #[test]
    fn a_tag_is_split_from_its_command() {
        assert_eq!(split(b"#42 set ratio 3"), Ok((Some(&b"42"[..]), &b"set ratio 3"[..])));
        assert_eq!(split(b"#999999 status"), Ok((Some(&b"999999"[..]), &b"status"[..])));
        assert_eq!(split(b"status"), Ok((None, &b"status"[..])));
        // a tag alone is an empty (tagged) command: the console answers it
        assert_eq!(split(b"#7"), Ok((Some(&b"7"[..]), &b""[..])));
    }

    #[test]
    fn malformed_tags_are_refused() {
        for bad in [&b"# status"[..], b"#1234567 status", b"#4a status", b"#-1 status", b"#"] {
            assert!(split(bad).is_err(), "{:?}", core::str::from_utf8(bad));
        }
    }
}
