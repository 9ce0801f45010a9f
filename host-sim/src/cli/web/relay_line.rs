//! What the relay lets a page send to the board: one console line, framed
//! as `polyturn device` frames it (the firmware's own `line::route` splits
//! the tag and the command), printable ASCII within the board's line
//! (`console_line::check_command`), not a line that reads as a reply
//! (`is_reply`), and not `dfu` (the sync core's own `console::parse`
//! decides what is `dfu`): flashing stays with the machine the board is
//! plugged into. A refusal is answered as the board answers, with the
//! line's tag, and says it came from the relay.

use super::super::console_line::{check_command, is_reply, DEVICE_LINE_MAX};
use polyturn_firmware::line::{route, Route};
use polyturn_sync::console::tag::{split, TAG_DIGITS};
use polyturn_sync::console::{parse, Command};

/// Why `dfu` is not relayed.
pub const NO_DFU: &str = "dfu is not relayed: flashing stays on the machine the board is plugged into (polyturn device dfu, then polyturn flash, there; or the Flash view in Chromium on it)";
/// Why a watching page's line is not sent.
pub const NOT_IN_CONTROL: &str = "another page has control of the board; this one watches";

/// The line to send to the board, or the reply to give the page instead.
pub fn check(line: &str) -> Result<(), String> {
    if line.len() > DEVICE_LINE_MAX {
        return Err(refusal(
            tag_of(line),
            &format!("the line is {} characters long: the board takes at most {DEVICE_LINE_MAX}", line.len()),
        ));
    }
    let (tag, to) = route(line.as_bytes()).map_err(|e| refusal(None, e))?;
    let tag = tag.and_then(|t| std::str::from_utf8(t).ok());
    let (_, body) = split(line.as_bytes()).map_err(|e| refusal(None, e))?;
    let command = std::str::from_utf8(body).map_err(|_| refusal(tag, "the line is not text"))?;
    check_command(command).map_err(|e| refusal(tag, &e.0))?;
    if is_reply(command) {
        return Err(refusal(tag, "the line reads as a reply: not sent"));
    }
    if matches!(to, Route::Console(c) if matches!(parse(c), Command::Dfu)) {
        return Err(refusal(tag, NO_DFU));
    }
    Ok(())
}

/// The reply a refused line gets: `#TAG error: relay: why`, untagged if
/// the line had no tag (or a malformed one).
pub fn refusal(tag: Option<&str>, why: &str) -> String {
    match tag {
        Some(t) => format!("#{t} error: relay: {why}"),
        None => format!("error: relay: {why}"),
    }
}

/// A well-formed tag's digits, for the refusal of a line too long to route.
pub fn tag_of(line: &str) -> Option<&str> {
    let rest = line.strip_prefix('#')?;
    let tag = rest.split(' ').next()?;
    (!tag.is_empty() && tag.len() <= TAG_DIGITS && tag.bytes().all(|b| b.is_ascii_digit())).then_some(tag)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn console_lines_pass_tagged_or_not() {
        for ok in ["#12 status", "status", "#1 set ratio 11/3", "#999999 get", "#3 cam data 0 1", "#4 engage"] {
            assert_eq!(check(ok), Ok(()), "{ok}");
        }
    }

    #[test]
    fn dfu_is_refused_with_the_reason_and_the_lines_tag() {
        for dfu in ["#7 dfu", "dfu", "#7  dfu ", "#7 dfu   "] {
            let e = check(dfu).unwrap_err();
            let want = if dfu.starts_with('#') {
                format!("#7 error: relay: {NO_DFU}")
            } else {
                format!("error: relay: {NO_DFU}")
            };
            assert_eq!(e, want, "{dfu:?}");
        }
        // a word that is not the command dfu goes to the board, which answers it
        assert_eq!(check("#8 dfu now"), Ok(()));
        assert_eq!(check("#8 dfuse"), Ok(()));
    }

    #[test]
    fn a_bad_tag_a_control_character_a_reply_or_an_overlong_line_is_refused() {
        assert_eq!(
            check("#x status").unwrap_err(),
            "error: relay: a tag is # and 1 to 6 digits, then a space and the command"
        );
        let e = check("#5 status\r#6 dfu").unwrap_err();
        assert!(e.starts_with("#5 error: relay: the command 'status\\r#6 dfu' holds a control character"), "{e}");
        assert!(check("#5 stat\u{e9}").unwrap_err().starts_with("#5 error: relay: the command"));
        assert_eq!(check("#6 ok engaged").unwrap_err(), "#6 error: relay: the line reads as a reply: not sent");
        assert_eq!(check("#6 error: x").unwrap_err(), "#6 error: relay: the line reads as a reply: not sent");
        let long = format!("#9 set ratio {}", "1".repeat(90));
        let e = check(&long).unwrap_err();
        assert!(e.starts_with("#9 error: relay: the line is 103 characters long: the board takes at most 96"), "{e}");
        assert_eq!(tag_of(&"x".repeat(200)), None);
    }
}
