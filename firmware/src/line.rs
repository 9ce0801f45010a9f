//! Assembles console lines from USB packets: CR, LF or CRLF ends a line;
//! an over-long line is dropped whole (and reported), never truncated into
//! a different command.

pub const LINE_MAX: usize = 96;

/// True if `bytes` hold nothing but line ends. `watch` starts only when
/// the rest of its packet is this (the LF of its CRLF, issue 13 review),
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
    fn an_over_long_line_is_dropped_whole() {
        let mut input = vec![b'x'; 200];
        input.extend_from_slice(b"\nstatus\n");
        assert_eq!(lines(&input), vec![Err(()), Ok("status".into())]);
    }
}
