//! Any bytes, one at a time, into the USB console's `LineBuffer` (the
//! caller clears it after each line, as the firmware does). With the input
//! followed by one LF, split at every CR and LF into segments: the buffer
//! returns exactly one item per non-empty segment, in order and at that
//! segment's terminator (never at another byte): `Text(segment)` if it is at
//! most `LINE_MAX` bytes, `TooLong` if longer; nothing for an empty segment
//! (a CRLF's LF, a blank line). So a line never exceeds the bound, never
//! holds a CR or LF, is never cut short into a different command, and the
//! lines returned are the input's short lines, concatenated in order.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polyturn_firmware::line::{Line, LineBuffer, LINE_MAX};

#[derive(Debug, PartialEq, Eq)]
enum Item<'a> {
    Text(&'a [u8]),
    TooLong,
}

fuzz_target!(|data: &[u8]| {
    let mut input = data.to_vec();
    input.push(b'\n');
    let eol = |b: &u8| *b == b'\r' || *b == b'\n';
    // the model: segments between terminators (the last, after the final
    // LF, is empty and never terminated)
    let mut segments = input.split(eol).collect::<Vec<_>>();
    segments.pop();
    let expected: Vec<Item> = segments
        .iter()
        .filter(|s| !s.is_empty())
        .map(|s| if s.len() <= LINE_MAX { Item::Text(s) } else { Item::TooLong })
        .collect();

    let mut buf = LineBuffer::default();
    let mut got: Vec<Vec<u8>> = Vec::new(); // Text lines, owned
    let mut kinds: Vec<Option<usize>> = Vec::new(); // Some(index into got) or TooLong
    for (at, b) in input.iter().enumerate() {
        let item = buf.push(*b);
        if item.is_some() {
            assert!(eol(b), "a line returned at byte {at} ({b:#04x}), not at a line end");
        }
        match item {
            Some(Line::Text(t)) => {
                assert!(!t.is_empty() && t.len() <= LINE_MAX, "line of {} bytes", t.len());
                assert!(!t.iter().any(eol));
                kinds.push(Some(got.len()));
                got.push(t.to_vec());
            }
            Some(Line::TooLong) => kinds.push(None),
            None => continue,
        }
        buf.clear();
    }
    let got: Vec<Item> = kinds.iter().map(|k| k.map_or(Item::TooLong, |i| Item::Text(&got[i]))).collect();
    assert_eq!(got, expected);
});
