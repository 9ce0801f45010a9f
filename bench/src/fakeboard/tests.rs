//! The fake board frames lines as the firmware does:
//! the same bound, the same untagged refusal of an over-long line, every
//! byte kept, `cam` lines to the upload, and no unbounded buffer.

use super::*;

fn replies(dev: &mut FakeDevice, input: &[u8]) -> String {
    dev.write_all(input).unwrap();
    String::from_utf8_lossy(&dev.take_replies()).into_owned()
}

#[test]
fn a_line_over_96_bytes_is_dropped_whole_and_answered_untagged_as_the_firmware_does() {
    let mut dev = FakeDevice::new();
    let exact = format!("#1 status{}", " ".repeat(polyturn_firmware::line::LINE_MAX - 9));
    assert_eq!(exact.len(), 96);
    assert!(replies(&mut dev, format!("{exact}\r\n").as_bytes()).starts_with("#1 ok state=idle"));
    let over = format!("{exact} \r\n");
    assert_eq!(replies(&mut dev, over.as_bytes()), "error: line too long (96 characters at most)\r\n");
    // the next line is a line of its own again
    assert_eq!(replies(&mut dev, b"#2 get edges\r\n"), "#2 ok edges=3\r\n");
}

#[test]
fn megabytes_without_a_newline_are_neither_kept_nor_answered_as_a_command() {
    let mut dev = FakeDevice::new();
    let chunk = vec![b'x'; 1 << 20];
    for _ in 0..50 {
        assert_eq!(dev.write(&chunk).unwrap(), chunk.len(), "taken: no reply waits");
    }
    assert!(dev.take_replies().is_empty(), "nothing answered before the line ends");
    assert_eq!(
        replies(&mut dev, b"\n#3 status\n").lines().next(),
        Some("error: line too long (96 characters at most)")
    );
    assert_eq!(dev.received, vec!["#3 status"], "the long line never reached the console");
}

#[test]
fn binary_bytes_stay_in_the_line_and_the_console_answers_them() {
    let mut dev = FakeDevice::new();
    assert_eq!(replies(&mut dev, b"#4 \xffstatus\r\n"), "#4 error: not text: commands are plain ASCII (try help)\r\n");
    assert_eq!(replies(&mut dev, b"#5 stat\0us\r\n"), "#5 error: unknown command or wrong arguments (try help)\r\n");
}

#[test]
fn cam_off_goes_to_the_cam_as_on_the_firmware() {
    let mut dev = FakeDevice::new();
    assert_eq!(replies(&mut dev, b"#6 cam off\r\n"), "#6 ok cam off (save to forget it)\r\n");
    // cam is a word: camera and camoff are unknown commands, as on the firmware
    assert_eq!(replies(&mut dev, b"#7 camera\r\n"), "#7 error: unknown command or wrong arguments (try help)\r\n");
    assert_eq!(replies(&mut dev, b"#8 camoff\r\n"), "#8 error: unknown command or wrong arguments (try help)\r\n");
}

#[test]
fn replies_nobody_reads_stop_the_board_taking_input_at_a_bound() {
    let mut dev = FakeDevice::new();
    let lines = b"#8 help\r\n".repeat(100_000);
    let taken = dev.write(&lines).unwrap();
    assert!(taken < lines.len(), "not all taken");
    // at most one packet's replies past the bound: a 64-byte packet ends
    // at most 8 of these 9-byte lines, each reply at most a console reply
    // with its tag and line end
    let one_packet = (PACKET_MAX / 9 + 1) * (polyturn_sync::console::REPLY_LEN + 5);
    assert!(dev.out.len() < OUT_MAX + one_packet, "{} bytes waiting", dev.out.len());
    assert_eq!(dev.write(b"#9 status\r\n").unwrap_err().kind(), ErrorKind::WouldBlock);
    dev.take_replies();
    // the packet taken last may have ended inside a line: end it first
    let r = replies(&mut dev, b"\r\n#9 status\r\n");
    // (its reply, if any, comes first: the status reply starts a line)
    assert!(r.starts_with("#9 ok state=") || r.contains("\r\n#9 ok state="), "{r:?}");
}

#[test]
fn a_watch_ends_at_the_next_packet_and_a_packet_of_line_ends_does_not_end_it() {
    let mut dev = FakeDevice::new();
    assert!(replies(&mut dev, b"watch\r\n").starts_with("ok state=idle"));
    assert!(replies(&mut dev, b"\n").is_empty());
    assert!(!dev.watch_line().is_empty(), "still watching");
    // `watch` with the next command in its packet: the watch never starts
    assert!(replies(&mut dev, b"#1 status\r\n").starts_with("#1 ok"));
    assert!(dev.watch_line().is_empty());
    replies(&mut dev, b"watch\r\n#2 get edges\r\n");
    assert!(dev.watch_line().is_empty(), "bytes after watch in its packet end it before it starts");
}

/// `status`'s fields as (name, value) after `ticks` pass on the machine.
fn status_after(dev: &mut FakeDevice, seconds: f64) -> std::collections::HashMap<String, String> {
    let m = dev.workshop.as_mut().unwrap();
    m.pass(&mut dev.ctl, (seconds * TICK_HZ as f64) as usize);
    let line = replies(dev, b"status\n");
    line.split_whitespace().filter_map(|kv| kv.split_once('=')).map(|(k, v)| (k.into(), v.into())).collect()
}

#[test]
fn a_lathe_set_turning_ramps_to_its_speed_and_the_cutter_syncs_to_it() {
    let mut dev = FakeDevice::new();
    dev.workshop = Some(Workshop::new(ticks_in_ms(10)));
    dev.workshop.as_mut().unwrap().set_lathe_rpm(600.0);
    let s = status_after(&mut dev, 0.5);
    let half: f64 = s["lathe_rpm"].parse().unwrap();
    assert!((250.0..350.0).contains(&half), "ramping at 600 rpm/s: {s:?}");
    let s = status_after(&mut dev, 1.5);
    // the core's estimate of the lathe's speed, not the model's own figure
    let steady: f64 = s["lathe_rpm"].parse().unwrap();
    assert!((steady - 600.0).abs() < 2.0, "{s:?}");
    assert!(replies(&mut dev, b"engage\n").starts_with("ok engaging"));
    let s = status_after(&mut dev, 3.0);
    assert_eq!(s["state"], "synced", "{s:?}");
    let cutter_rpm: f64 = s["cutter_rpm"].parse().unwrap();
    assert!((cutter_rpm - 1200.0).abs() < 4.0, "ratio 2: {s:?}");
    let cutter: i64 = s["cutter"].parse().unwrap();
    let later: i64 = status_after(&mut dev, 0.1)["cutter"].parse().unwrap();
    // 1200 rpm x 3200 steps a turn = 64 000 steps/s: 7040 in the 0.1 s
    // passed and the 10 ms before the `status` line
    assert!((later - cutter - 7040).abs() <= 2, "{cutter} -> {later}");
    // stopped, the lathe ramps to rest and the hand on the chuck is back
    assert!(replies(&mut dev, b"stop\n").starts_with("ok"));
    dev.workshop.as_mut().unwrap().set_lathe_rpm(0.0);
    let s = status_after(&mut dev, 2.0);
    assert_eq!((s["state"].as_str(), s["lathe_rpm"].as_str()), ("idle", "0.0"), "{s:?}");
    assert_eq!(dev.workshop.as_ref().unwrap().lathe_rpm(), 0.0);
}

fn field<'a>(line: &'a str, name: &str) -> &'a str {
    line.split_whitespace().find_map(|kv| kv.strip_prefix(name).and_then(|v| v.strip_prefix('='))).unwrap_or("?")
}

/// The machinist's hand on the chuck: it turns by what it is asked, at a
/// hand's pace, either way, and the board sees it through its encoder
/// and its index (at count 5 of each turn).
#[test]
fn a_hand_turns_the_chuck_by_an_angle_either_way_and_the_board_reads_it() {
    let mut dev = FakeDevice::new();
    dev.workshop = Some(Workshop::new(TICK_HZ as usize)); // 1 s of the board before each line
    dev.workshop.as_mut().unwrap().turn_by_hand(405);
    let status = replies(&mut dev, b"status\n");
    assert_eq!((field(&status, "angle_deg"), field(&status, "angle_from")), ("60.0", "index"), "{status}");
    assert_eq!(field(&status, "fault"), "none");
    dev.workshop.as_mut().unwrap().turn_by_hand(-810);
    let status = replies(&mut dev, b"status\n");
    // back 405 counts past the index at 5: 2400 - 410 from it
    assert_eq!(field(&status, "angle_deg"), "298.5", "{status}");
    // a turn takes the hand about 2 s: half a second turns 600 counts
    dev.workshop.as_mut().unwrap().ticks_per_line = TICK_HZ as usize / 2;
    dev.workshop.as_mut().unwrap().turn_by_hand(1_200);
    let status = replies(&mut dev, b"status\n");
    assert_eq!(field(&status, "angle_deg"), "28.5", "{status}");
}
