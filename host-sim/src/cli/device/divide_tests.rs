//! `polyturn device divide` against the real console on a fake board whose
//! chuck a hand turns (`Workshop::turn_by_hand`).

use super::divide::{divide, large, Look, Readout};
use super::tests::{session, FakeDevice};
use polyturn_bench::fakeboard::Workshop;
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// A board whose chuck the hand turns by `counts` as its time passes: a
/// tenth of a second for each `watch` line, none for a command.
fn board(counts: i64) -> super::session::Session<FakeDevice> {
    let mut dev = FakeDevice::new();
    let mut m = Workshop::new(0);
    m.turn_by_hand(counts);
    dev.workshop = Some(m);
    session(dev)
}

/// The terminal: it keeps what is shown, and the machinist presses Ctrl-C
/// once the readout has said `until`, or after `LINES_MAX` lines (a minute
/// of the board's: the hand has long stopped) whatever it said.
struct Watcher<'a> {
    shown: Vec<u8>,
    until: &'a str,
    stop: &'a AtomicBool,
}

impl Write for Watcher<'_> {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.shown.extend_from_slice(data);
        let text = String::from_utf8_lossy(&self.shown);
        if text.contains(self.until) || text.lines().count() > LINES_MAX {
            self.stop.store(true, Ordering::SeqCst);
        }
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

const LINES_MAX: usize = 600;

fn run(s: &mut super::session::Session<FakeDevice>, n: u32, until: &str) -> (String, Vec<String>) {
    let stop = AtomicBool::new(false);
    let mut w = Watcher { shown: vec![], until, stop: &stop };
    let end = divide(s, &format!("divide {n}"), &mut w, &stop, Look::Plain).unwrap();
    let shown = String::from_utf8(w.shown).unwrap();
    (end, shown.lines().map(String::from).collect())
}

#[test]
fn turned_forward_past_the_index_the_readout_finds_a_division_and_ctrl_c_ends_it_on_the_board() {
    // the index at count 5: division 1 of 6 is 405 counts on
    let mut s = board(405);
    let (end, lines) = run(&mut s, 6, "division 1 of 6 (60.0°): turn 0.0° (0.00 counts): WITHIN");
    assert_eq!(end, "ok divide ended");
    assert_eq!(
        lines[0],
        "division 0 of 6 (0.0°): turn 0.0° (0.00 counts): WITHIN ±1 count | spindle 0.0° from where the board started: no index seen yet, turn past it to fix the origin"
    );
    assert!(lines.iter().any(|l| l.contains(": not there | spindle ")), "on the way: {lines:?}");
    let last = lines.last().unwrap();
    assert!(last.ends_with("WITHIN ±1 count | spindle 60.0° from the index"), "{last}");
    // the board was told to divide, watched, and told to stop both
    let heard = &s.io.received;
    let said = |w: &str| heard.iter().position(|l| l.ends_with(w)).unwrap_or_else(|| panic!("{w}: {heard:?}"));
    assert!(
        said(" divide 6") < said(" watch")
            && said(" watch") < said(" status")
            && said(" status") < said(" divide stop")
    );
    assert_eq!(s.io.ctl.dividing(), None);
}

#[test]
fn turned_back_from_the_start_the_readout_counts_down_through_the_turn() {
    // back 400 counts from where the board started: division 5 of 6
    let mut s = board(-400);
    let (_, lines) = run(&mut s, 6, "division 5 of 6 (300.0°): turn 0.0° (0.00 counts): WITHIN");
    let last = lines.last().unwrap();
    assert!(last.contains("spindle 300.0° from where the board started"), "{last}");
    // on the way: short of division 5, the way to turn is back (negative)
    assert!(lines.iter().any(|l| l.starts_with("division 5 of 6 (300.0°): turn -")), "{lines:?}");
}

#[test]
fn a_refused_number_is_the_boards_error_and_nothing_is_watched() {
    let mut s = board(0);
    let stop = AtomicBool::new(false);
    let mut out = Vec::new();
    let e = divide(&mut s, "divide 601", &mut out, &stop, Look::Plain).unwrap_err();
    assert_eq!(e.0, "device: error: divide 1..=3600 divisions of a turn, at most cpr/4 (4 counts or more apart)");
    assert!(out.is_empty());
    assert!(!s.io.received.iter().any(|l| l.ends_with(" watch")));
}

#[test]
fn the_large_readout_is_green_within_a_count_and_redrawn_in_place() {
    let line = "ok state=idle fault=none indexed=yes angle_deg=59.9 angle_from=index divide=6 division=1 \
                division_deg=60.0 to_deg=0.2 to_counts=1.00 within=yes";
    let r = Readout::parse(line).unwrap();
    let big = r.big();
    assert_eq!(big[0], "DIVISION 1 OF 6  at 60.0°");
    assert_eq!(&big[1..6], large("+0.2°").iter().map(|l| format!("\x1b[1;32m{l}\x1b[0m")).collect::<Vec<_>>());
    assert_eq!(big[6], "\x1b[1;32m+1.00 counts to turn   WITHIN ±1 count\x1b[0m");
    let far = Readout::parse(&line.replace("to_counts=1.00 within=yes", "to_counts=2.00 within=no")).unwrap();
    assert!(far.big()[1].starts_with("\x1b[1m") && far.big()[6].contains("not there"));
    // a plus: a bar across and one down through it, in block characters
    assert_eq!(large("+")[1..4], ["  ██", "██████", "  ██"]);
    let pad = " ".repeat(8);
    assert_eq!(
        large("-0"),
        [
            format!("{pad}██████"),
            format!("{pad}██  ██"),
            "██████  ██  ██".into(),
            format!("{pad}██  ██"),
            format!("{pad}██████")
        ]
    );
}
