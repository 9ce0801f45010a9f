//! The relay against the fake board (the real console behind the
//! firmware's framing), in process: who has control, what reaches the
//! board, what every page hears, and the board going away.

use super::*;
use polyturn_bench::fakeboard::FakeDevice;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The fake board's two ends, and a switch that makes it go away.
#[derive(Clone)]
struct Shared {
    board: Arc<Mutex<FakeDevice>>,
    unplugged: Arc<AtomicBool>,
}

impl Read for Shared {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.unplugged.load(Ordering::SeqCst) {
            return Err(std::io::Error::other("Input/output error (os error 5)"));
        }
        self.board.lock().unwrap().read(buf)
    }
}

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.board.lock().unwrap().write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

struct Bench {
    relay: Arc<Relay>,
    board: Shared,
    opened: Arc<AtomicUsize>,
}

fn bench() -> Bench {
    let board = Shared { board: Arc::new(Mutex::new(FakeDevice::new())), unplugged: Arc::new(AtomicBool::new(false)) };
    let opened = Arc::new(AtomicUsize::new(0));
    let (b, o) = (board.clone(), Arc::clone(&opened));
    let open: Opener = Box::new(move || {
        o.fetch_add(1, Ordering::SeqCst);
        if b.unplugged.load(Ordering::SeqCst) {
            return Err("cannot open /dev/ttyACM0: No such file or directory".into());
        }
        Ok((Box::new(b.clone()) as Box<dyn Read + Send>, Box::new(b.clone()) as Box<dyn Write + Send>))
    });
    let relay = Relay::start("/dev/ttyACM0", open).unwrap();
    Bench { relay, board, opened }
}

/// The next event that is not a board line other than `#tag ...`.
fn next(m: &Member) -> Event {
    m.events.recv_timeout(Duration::from_secs(5)).expect("an event within 5 s")
}

/// Waits for the line tagged `tag`, skipping others (status lines).
fn reply(m: &Member, tag: &str) -> String {
    loop {
        if let Event::Line { line } = next(m) {
            if let Some(r) = line.strip_prefix(&format!("#{tag} ")) {
                return r.to_string();
            }
        }
    }
}

fn greeting(m: &Member) -> Event {
    assert!(matches!(next(m), Event::Hello { port, .. } if port == "/dev/ttyACM0"));
    next(m)
}

#[test]
fn the_first_page_has_control_and_every_page_hears_the_board() {
    let b = bench();
    let first = b.relay.join().unwrap();
    let second = b.relay.join().unwrap();
    assert_eq!(greeting(&first), Event::Control { yours: true, free: false });
    assert_eq!(greeting(&second), Event::Control { yours: false, free: false });
    b.relay.send(first.id, "#5 get edges").unwrap();
    assert_eq!(reply(&first, "5"), "ok edges=3");
    assert_eq!(reply(&second, "5"), "ok edges=3", "a watching page hears the replies too");
}

#[test]
fn a_second_page_is_refused_control_and_its_lines_never_reach_the_board() {
    let b = bench();
    let first = b.relay.join().unwrap();
    let second = b.relay.join().unwrap();
    let _ = (greeting(&first), greeting(&second));
    assert_eq!(
        b.relay.send(second.id, "#9 set edges 4"),
        Err(format!("#9 error: relay: {}", relay_line::NOT_IN_CONTROL))
    );
    assert_eq!(b.relay.take(second.id), Err(relay_line::NOT_IN_CONTROL.to_string()));
    assert!(!b.board.board.lock().unwrap().received.iter().any(|l| l.contains("edges")), "the watcher's line was sent");
    // the controlling page goes: control is free, and the other may take it
    b.relay.leave(first.id);
    assert_eq!(next(&second), Event::Control { yours: false, free: true });
    b.relay.take(second.id).unwrap();
    assert_eq!(next(&second), Event::Control { yours: true, free: false });
    b.relay.send(second.id, "#10 set edges 4").unwrap();
    assert_eq!(reply(&second, "10"), "ok edges=4");
}

#[test]
fn dfu_is_refused_over_the_relay_and_never_sent() {
    let b = bench();
    let page = b.relay.join().unwrap();
    let e = b.relay.send(page.id, "#3 dfu").unwrap_err();
    assert_eq!(e, format!("#3 error: relay: {}", relay_line::NO_DFU));
    b.relay.send(page.id, "#4 status").unwrap();
    assert!(reply(&page, "4").starts_with("ok state=idle"));
    let received = b.board.board.lock().unwrap().received.clone();
    assert!(!received.iter().any(|l| l.contains("dfu")), "{received:?}");
    assert!(received.iter().any(|l| l == "#4 status"), "{received:?}");
}

#[test]
fn a_board_that_goes_away_lets_every_page_go_and_sends_nothing_again() {
    let b = bench();
    let (first, second) = (b.relay.join().unwrap(), b.relay.join().unwrap());
    let _ = (greeting(&first), greeting(&second));
    b.board.unplugged.store(true, Ordering::SeqCst);
    for m in [&first, &second] {
        match next(m) {
            Event::Gone { why } => assert!(
                why.starts_with("the board on /dev/ttyACM0 went away (Input/output error (os error 5))")
                    && why.contains("Nothing that was waiting for a reply was sent again"),
                "{why}"
            ),
            e => panic!("{e:?}"),
        }
        let after = m.events.recv_timeout(Duration::from_millis(200));
        assert_eq!(after, Err(std::sync::mpsc::RecvTimeoutError::Disconnected), "the page is let go");
    }
    assert_eq!(
        b.relay.send(first.id, "#6 status"),
        Err("#6 error: relay: the board has gone: nothing was sent".into())
    );
    // a page that connects again opens the port again, or hears why not
    assert_eq!(b.relay.join().err(), Some("cannot open /dev/ttyACM0: No such file or directory".to_string()));
    b.board.unplugged.store(false, Ordering::SeqCst);
    let again = b.relay.join().unwrap();
    assert_eq!(greeting(&again), Event::Control { yours: true, free: false });
    assert_eq!(b.opened.load(Ordering::SeqCst), 3);
    b.relay.send(again.id, "#7 get edges").unwrap();
    assert_eq!(reply(&again, "7"), "ok edges=3");
    let received = b.board.board.lock().unwrap().received.clone();
    assert_eq!(received.iter().filter(|l| l.starts_with("#6")).count(), 0, "{received:?}");
}

#[test]
fn no_more_pages_than_the_bound_are_let_in() {
    let b = bench();
    let members: Vec<_> = (0..MEMBERS_MAX).map(|_| b.relay.join().unwrap()).collect();
    assert_eq!(b.relay.join().err(), Some(format!("{MEMBERS_MAX} pages already have the board: close one")));
    b.relay.leave(members[3].id);
    assert!(b.relay.join().is_ok());
}

#[test]
fn an_overlong_line_from_the_board_is_dropped_whole_with_a_notice() {
    let mut lines = Lines::default();
    let mut long = vec![b'x'; REPLY_MAX + 5];
    long.extend_from_slice(b" ok\r\n#1 ok edges=3\r\n");
    let events = lines.push(&long);
    assert_eq!(events.len(), 2, "{events:?}");
    assert!(matches!(&events[0], Event::Notice { why } if why.contains("longer than 512 bytes")));
    assert_eq!(events[1], Event::Line { line: "#1 ok edges=3".into() });
    // a line split across reads is one line; one of exactly REPLY_MAX passes
    assert_eq!(lines.push(b"#2 ok"), vec![]);
    assert_eq!(lines.push(b" cpr=2400\n"), vec![Event::Line { line: "#2 ok cpr=2400".into() }]);
    let exact = format!("{}\r\n", "y".repeat(REPLY_MAX));
    assert_eq!(lines.push(exact.as_bytes()), vec![Event::Line { line: "y".repeat(REPLY_MAX) }]);
}

#[test]
fn a_port_that_cannot_be_opened_is_refused_at_start() {
    let open: Opener = Box::new(|| Err("cannot open COM9: The system cannot find the file specified.".into()));
    assert_eq!(
        Relay::start("COM9", open).err(),
        Some("cannot open COM9: The system cannot find the file specified.".into())
    );
}
