//! Assembles console lines from USB packets: CR, LF or CRLF ends a line;
//! an over-long line is dropped whole (and reported), never truncated into
//! a different command. Every byte but CR and LF is kept as it came (a NUL,
//! a byte over 127): the console answers what is not text. The fake board
//! (`polyturn_bench::fakeboard`) frames with this same code, so the two
//! cannot differ.

use polyturn_sync::console::tag;

pub const LINE_MAX: usize = 96;
/// The largest USB full-speed bulk packet: the console reads one at a time.
pub const PACKET_MAX: usize = 64;
/// The reply to a line longer than `LINE_MAX`, untagged (its tag may be
/// anything: the line was not kept).
pub const TOO_LONG: &str = "error: line too long (96 characters at most)";

/// Where a line's command goes once its tag is off: the cam upload (the
/// word `cam`, alone or followed by a space: what follows it) or the sync
/// core's console (everything else, `camoff` and `camera` included: those
/// are unknown commands, not cam lines).
#[derive(Debug, PartialEq, Eq)]
pub enum Route<'a> {
    Cam(&'a [u8]),
    Console(&'a [u8]),
}

/// Splits a line as the console task answers it: its tag's digits (if
/// tagged) and where the rest goes; a malformed tag's error, answered
/// untagged.
pub fn route(line: &[u8]) -> Result<(Option<&[u8]>, Route<'_>), &'static str> {
    let (tag, body) = tag::split(line)?;
    let to = match body.strip_prefix(b"cam") {
        Some(args) if args.is_empty() || args[0] == b' ' => Route::Cam(args),
        _ => Route::Console(body),
    };
    Ok((tag, to))
}

/// True if `bytes` hold nothing but line ends. `watch` starts only when
/// the rest of its packet is this (the LF of its CRLF),
/// and a packet of only line ends does not end a watch (the LF of a CRLF
/// split across packets): any other byte is the next input.
pub fn only_line_ends(bytes: &[u8]) -> bool {
    bytes.iter().all(|&b| b == b'\r' || b == b'\n')
}

#[derive(Default)]
pub struct LineBuffer {
    buf: heapless::Vec<u8, LINE_MAX>,
    overflow: bool,
}

/// One assembled line, or the news that one was too long.
#[derive(Debug, PartialEq, Eq)]
pub enum Line<'a> {
    Text(&'a [u8]),
    TooLong,
}

impl LineBuffer {
    /// Feeds one byte; returns a line when it ends.
    pub fn push(&mut self, byte: u8) -> Option<Line<'_>> {
        if byte == b'\r' || byte == b'\n' {
            let over = core::mem::take(&mut self.overflow);
            if over {
                self.buf.clear();
                return Some(Line::TooLong);
            }
            if self.buf.is_empty() {
                return None; // the LF of a CRLF, or a blank line
            }
            return Some(Line::Text(&self.buf));
        }
        if self.buf.push(byte).is_err() {
            self.overflow = true;
        }
        None
    }

    /// Call after handling a returned line.
    pub fn clear(&mut self) {
        self.buf.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(input: &[u8]) -> Vec<Result<String, ()>> {
        let mut b = LineBuffer::default();
        let mut out = Vec::new();
        for &c in input {
            match b.push(c) {
                Some(Line::Text(t)) => out.push(Ok(String::from_utf8_lossy(t).into_owned())),
                Some(Line::TooLong) => out.push(Err(())),
                None => continue,
            }
            b.clear();
        }
        out
    }

    #[test]
    fn a_watch_starts_only_when_nothing_but_its_line_end_follows() {
        // `#5 watch\r\n` in one packet: the LF after the line's CR
        assert!(only_line_ends(b"\n") && only_line_ends(b"") && only_line_ends(b"\r\n"));
        // anything else is the next input: the watch ends before it starts
        assert!(!only_line_ends(b"\nstatus") && !only_line_ends(b" "));
    }

    #[test]
    fn crlf_cr_and_lf_all_end_lines() {
        assert_eq!(
            lines(b"status\r\nset ratio 2\rengage\n"),
            vec![Ok("status".into()), Ok("set ratio 2".into()), Ok("engage".into())]
        );
    }

    #[test]
    fn a_line_is_routed_to_the_cam_upload_or_the_console_with_its_tag() {
        assert_eq!(route(b"#7 cam data 0 1"), Ok((Some(&b"7"[..]), Route::Cam(b" data 0 1"))));
        assert_eq!(route(b"camera"), Ok((None, Route::Console(b"camera"))), "cam is a word");
        assert_eq!(route(b"camoff"), Ok((None, Route::Console(b"camoff"))), "not cam off");
        assert_eq!(route(b"cam"), Ok((None, Route::Cam(b""))));
        assert_eq!(route(b"#12 status"), Ok((Some(&b"12"[..]), Route::Console(b"status"))));
        assert_eq!(route(b" cam off"), Ok((None, Route::Console(b" cam off"))));
        assert!(route(b"#x status").is_err());
    }

    #[test]
    fn a_line_of_exactly_line_max_bytes_is_kept_and_one_more_is_too_long() {
        let mut input = vec![b'y'; LINE_MAX];
        input.push(b'\n');
        input.extend(vec![b'z'; LINE_MAX + 1]);
        input.push(b'\r');
        assert_eq!(lines(&input), vec![Ok("y".repeat(LINE_MAX)), Err(())]);
    }

    #[test]
    fn binary_bytes_are_kept_in_the_line_and_only_cr_and_lf_end_it() {
        let mut b = LineBuffer::default();
        for &c in b"\0\x1b\xff" {
            assert_eq!(b.push(c), None);
        }
        assert_eq!(b.push(b'\r'), Some(Line::Text(&b"\0\x1b\xff"[..])));
    }

    #[test]
    fn an_over_long_line_is_dropped_whole() {
        let mut input = vec![b'x'; 200];
        input.extend_from_slice(b"\nstatus\n");
        assert_eq!(lines(&input), vec![Err(()), Ok("status".into())]);
    }
}
