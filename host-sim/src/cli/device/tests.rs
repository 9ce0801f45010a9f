//! The host's side of the console protocol against the real sync-core
//! console (a fake device that frames and tags lines as the firmware's
//! `usb.rs` does) and against devices that misbehave.

use super::session::{check_command, Session, COMMAND_MAX};
use super::{send_table, upload, watch};
pub(super) use polyturn_bench::fakeboard::FakeDevice;
use std::io::{ErrorKind, Read, Write};
use std::time::Duration;

pub(super) fn session<T: Read + Write>(io: T) -> Session<T> {
    Session::new(io, "/dev/fake", Duration::from_millis(300))
}

#[test]
fn the_host_speaks_the_firmware_console_protocol() {
    let mut s = session(FakeDevice::new());
    assert_eq!(s.ask("set max-rpm 600").unwrap(), "ok max-rpm=600");
    assert_eq!(s.ask("set ratio 11/3").unwrap(), "ok ratio=11/3");
    assert!(s.ask("status").unwrap().starts_with("ok state=idle"));
    assert!(s.ask("set ratio 0").unwrap_err().0.starts_with("device: error: ratio"));
}

#[test]
fn a_command_after_a_watch_gets_its_own_reply_not_a_status_line() {
    let mut s = session(FakeDevice::new());
    s.ask("watch").unwrap();
    // the device streams status lines; the next command's reply is the
    // line with its tag, and the command is applied
    assert_eq!(s.ask("set edges 4").unwrap(), "ok edges=4");
    assert_eq!(s.ask("get edges").unwrap(), "ok edges=4");
}

#[test]
fn a_watch_ends_on_the_board_before_it_returns() {
    super::INTERRUPTED.store(true, std::sync::atomic::Ordering::SeqCst); // Ctrl-C at once
    let mut s = session(FakeDevice::new());
    let mut out = Vec::new();
    watch(&mut s, &mut out).unwrap();
    super::INTERRUPTED.store(false, std::sync::atomic::Ordering::SeqCst);
    assert!(String::from_utf8(out).unwrap().starts_with("ok state=idle"));
    // the board was sent a tagged status, which ends its watch
    assert!(s.ask("get ratio").unwrap().starts_with("ok ratio="));
}

#[test]
fn a_cam_table_uploads_through_the_real_console() {
    use crate::noncircular::path::Polygon;
    use crate::noncircular::plan::{plan, Axis, Outcome};
    let axis = Axis { rpm: 12.0, max_speed: 12.0, max_accel: 2000.0 };
    let Outcome::Sharp(path, _) = plan(Polygon { sides: 8, apothem_mm: 20.0 }, 3, axis) else { panic!("sharp") };
    let table = crate::noncircular::table::build(&path, 2400, 800.0, (9_600, 1_600_000));
    for line in table.upload_lines(COMMAND_MAX) {
        assert!(line.len() <= COMMAND_MAX, "{} > {COMMAND_MAX}: {line}", line.len());
    }
    let mut s = session(FakeDevice::new());
    // a single-point tool's table, on a board with a cutter: nothing sent
    let e = upload(&mut s, &table).unwrap_err().0;
    assert!(e.starts_with("upload-cam: the table is a single-point tool's (polyturn cam), the board is set to drive=stepper: set drive none first"), "{e}");
    s.ask("set drive none").unwrap();
    // a table for another encoder: refused before anything is sent
    s.ask("set cpr 2000").unwrap();
    let e = upload(&mut s, &table).unwrap_err().0;
    assert!(e.starts_with("upload-cam: the table was made for a lathe encoder of 2400 counts a turn (counts_per_rev), the board's cpr is 2000"), "{e}");
    s.ask("set cpr 2400").unwrap();
    // the fake device stages and checks the table as the firmware does;
    // it has no flash, and its last reply says so
    let r = upload(&mut s, &table).unwrap();
    assert!(r.starts_with(&format!("ok cam {} points checked", table.header().points)), "{r}");
    // a line out of order abandons the upload, in the firmware's words
    let e = s.ask("cam data 0 1 2").unwrap_err().0;
    assert!(e.contains("start again with cam begin"), "{e}");
}

/// A compensating table from `polyturn compensate --table` goes to a board
/// set up for its cutter, and to no other: nothing is sent.
#[test]
fn a_compensating_table_goes_only_to_a_board_set_for_its_ratio_and_edges() {
    use crate::geometry::{Direction, Setup};
    let setup = Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 2.0,
        ratio: polyturn_sync::Ratio::parse("3").unwrap(),
        edges: 2,
        direction: Direction::Same,
    };
    let plan = crate::compensate::plan(&setup, 20.0, 12.5, 5000.0);
    let table = crate::compensate::table::cam_file(&setup, &plan, 2400, 800.0, (10_000, 4_000_000));
    let mut s = session(FakeDevice::new());
    s.ask("set max-rpm 600").unwrap(); // room for ratio 3 at max-rate
    s.ask("set ratio 2").unwrap();
    s.ask("set edges 3").unwrap();
    let e = upload(&mut s, &table).unwrap_err().0;
    assert_eq!(e, "upload-cam: the table was made for ratio 3 with 2 edges, the board is set to ratio 2 with 3 edges: set ratio and edges on the board (after polyturn device cam-off, if a table is fitted), or make the table for its setup (nothing sent)");
    let e = s.ask("cam end 00000000").unwrap_err().0;
    assert!(e.contains("cam begin"), "no table was begun: {e}");
    s.ask("set ratio 3/1").unwrap();
    assert!(upload(&mut s, &table).unwrap_err().0.contains("with 3 edges"), "the edges differ still");
    s.ask("set edges 2").unwrap();
    let r = upload(&mut s, &table).unwrap();
    assert!(r.starts_with("ok cam 400 points checked"), "{r}");
    // and no cutter at all is refused before anything is sent
    let mut s = session(FakeDevice::new());
    s.ask("set drive none").unwrap();
    let e = upload(&mut s, &table).unwrap_err().0;
    assert!(e.starts_with("upload-cam: the table straightens the flats of a turning cutter (ratio 3 with 2 edges), the board is set to drive=none"), "{e}");
}

/// The 3:1 x 2 flats table `polyturn compensate --table` writes for a
/// cutter turning `direction` to the lathe.
fn flats_table(direction: crate::geometry::Direction) -> crate::noncircular::table::CamFile {
    use crate::geometry::Setup;
    let setup = Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 2.0,
        ratio: polyturn_sync::Ratio::parse("3").unwrap(),
        edges: 2,
        direction,
    };
    let plan = crate::compensate::plan(&setup, 20.0, 12.5, 5000.0);
    crate::compensate::table::cam_file(&setup, &plan, 2400, 800.0, (10_000, 4_000_000))
}

/// A board set for the flats table's ratio and edges, its cutter turning
/// `dir` to the lathe.
fn board_for_flats(dir: &str) -> Session<FakeDevice> {
    let mut s = session(FakeDevice::new());
    for line in ["set max-rpm 600", "set ratio 3", "set edges 2", &format!("set dir {dir}")] {
        s.ask(line).unwrap();
    }
    s
}

/// The other sense sweeps the stock the other way round, so a compensating
/// table goes only to a board turning its cutter in the sense it was made
/// for; refused before anything is sent, naming both.
#[test]
fn a_compensating_table_goes_only_to_a_board_turning_its_cutter_the_sense_it_was_made_for() {
    use crate::geometry::Direction;
    let mut s = board_for_flats("opposite");
    let e = upload(&mut s, &flats_table(Direction::Same)).unwrap_err().0;
    assert_eq!(e, "upload-cam: the table was made for direction same (the cutter turning the same way as the lathe), the board is set to dir=opposite: set dir same on the board (after polyturn device cam-off, if a table is fitted), or make the table with --direction opposite (nothing sent)");
    let e = s.ask("cam end 00000000").unwrap_err().0;
    assert!(e.contains("cam begin"), "no table was begun: {e}");
    let r = upload(&mut s, &flats_table(Direction::Opposite)).unwrap();
    assert!(r.starts_with("ok cam "), "{r}");
    let mut s = board_for_flats("same");
    let e = upload(&mut s, &flats_table(Direction::Opposite)).unwrap_err().0;
    assert!(e.starts_with("upload-cam: the table was made for direction opposite (the cutter turning the opposite way to the lathe), the board is set to dir=same: set dir opposite on the board"), "{e}");
    assert!(upload(&mut s, &flats_table(Direction::Same)).unwrap().starts_with("ok cam "));
}

/// The web page checks a table against the board's whole `get` reply
/// (`fits_settings`): the same refusal of the other sense.
#[test]
fn the_pages_check_refuses_a_compensating_table_for_the_other_sense_too() {
    use crate::geometry::Direction;
    let mut s = board_for_flats("opposite");
    let get = s.ask("get").unwrap();
    let e = flats_table(Direction::Same).fits_settings(&get).unwrap_err();
    assert!(e.starts_with("the table was made for direction same (the cutter turning the same way as the lathe), the board is set to dir=opposite"), "{e}");
    assert_eq!(flats_table(Direction::Opposite).fits_settings(&get), Ok(()));
}

/// A compensating table written without its sense (an older polyturn's)
/// still parses, but is refused rather than guessed at: the wrong sense
/// cuts another section, and the board refuses `set dir` once it is fitted.
#[test]
fn a_compensating_table_that_does_not_say_its_sense_is_refused_saying_how_to_remake_it() {
    let table = flats_table(crate::geometry::Direction::Same);
    let text = serde_json::to_string(&table).unwrap().replace(",\"direction\":\"same\"", "");
    assert!(!text.contains("direction"), "{text}");
    let old = crate::cli::console_line::cam_table("old.json", &text).expect("an older table parses");
    for dir in ["same", "opposite"] {
        let mut s = board_for_flats(dir);
        let e = upload(&mut s, &old).unwrap_err().0;
        assert_eq!(e, format!("upload-cam: the table does not say which sense its cutter turns (cutter.direction, which polyturn compensate --table writes; an older polyturn did not), and its X motion fits only one: make it again with polyturn compensate --direction {dir} --table FILE for the board's dir={dir} (nothing sent)"));
        let e = s.ask("cam end 00000000").unwrap_err().0;
        assert!(e.contains("cam begin"), "no table was begun: {e}");
    }
}

/// The board checks the points against the X axis the table declares
/// before it stores anything (the host checks first: this is the board's
/// own check, for a table sent past it).
#[test]
fn the_board_refuses_a_table_its_x_axis_cannot_follow_with_the_figures() {
    let points: Vec<i32> = (0..1024).map(|i| if i == 500 { 100_000 } else { 0 }).collect();
    let table = crate::noncircular::table::CamFile {
        format: crate::noncircular::table::FORMAT.into(),
        counts_per_rev: 2400,
        period_counts: 2400,
        steps_per_mm: 800.0,
        max_rate_hz: polyturn_sync::cam_upload::X_MAX_RATE_HZ,
        max_accel: 1_000_000,
        points,
        cutter: None,
    };
    let mut s = session(FakeDevice::new());
    s.ask("set drive none").unwrap();
    let e = upload(&mut s, &table).unwrap_err().0;
    assert_eq!(
        e,
        "device: error: cam table: neighbouring points 100000 steps apart need 1706650 X steps/s at 1 lathe rpm, beyond its max-rate 10000 steps/s (a table must be followed at 1 rpm or faster)"
    );
}

/// A complete table is saved only idle with the lathe at rest; the
/// refusal says which, and what the board saw of the lathe.
#[test]
fn a_table_not_saved_now_says_why() {
    let table = octagon_table();
    let mut dev = FakeDevice::new();
    dev.workshop = Some(polyturn_bench::fakeboard::Workshop::new(polyturn_bench::fakeboard::ticks_in_ms(10)));
    let mut s = session(dev);
    s.ask("engage").unwrap();
    // the board's own refusal (the host would refuse this table for the
    // cutter first)
    let e = send_table(&mut s, &table).unwrap_err().0;
    assert_eq!(
        e,
        "device: error: stop first: the cam changes only while idle (900 points kept, run upload-cam again to send it)"
    );
    s.ask("stop").unwrap();
    s.io.workshop.as_mut().unwrap().set_lathe_rpm(60.0);
    s.ask("status").unwrap();
    let e = send_table(&mut s, &table).unwrap_err().0;
    assert!(
        e.starts_with(
            "device: error: stop the lathe first: its encoder counted 0 ms ago (at rest after 100 ms without a count)"
        ),
        "{e}"
    );
    assert!(e.ends_with(": the table is saved to flash (900 points kept, run upload-cam again to send it)"), "{e}");
}

fn octagon_table() -> crate::noncircular::table::CamFile {
    use crate::noncircular::path::Polygon;
    use crate::noncircular::plan::{plan, Axis, Outcome};
    let axis = Axis { rpm: 12.0, max_speed: 12.0, max_accel: 2000.0 };
    let Outcome::Sharp(path, _) = plan(Polygon { sides: 8, apothem_mm: 20.0 }, 3, axis) else { panic!("sharp") };
    crate::noncircular::table::build(&path, 2400, 800.0, (9_600, 1_600_000))
}

#[test]
fn control_characters_and_long_commands_never_reach_the_board() {
    assert!(check_command("set phase 1\r\nset cpr 4000").unwrap_err().0.contains("control character (\\r)"));
    assert!(check_command("set phase 1\x1b[2J").is_err());
    assert!(check_command("set phase é").is_err());
    assert!(check_command(&"x".repeat(COMMAND_MAX + 1)).unwrap_err().0.contains("at most"));
    assert!(check_command("set phase -1.5").is_ok());
}

/// A device that answers every line with `answer` (bytes, as they come).
struct Misbehaving {
    answer: &'static [u8],
    endless: bool,
    sent: usize,
}

impl Read for Misbehaving {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.answer.is_empty() || (!self.endless && self.sent >= self.answer.len()) {
            return Err(ErrorKind::TimedOut.into());
        }
        let n = buf.len().min(self.answer.len());
        buf[..n].copy_from_slice(&self.answer[..n]);
        self.sent += n;
        Ok(n)
    }
}

impl Write for Misbehaving {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

fn against(answer: &'static [u8], endless: bool) -> String {
    let mut s = session(Misbehaving { answer, endless, sent: 0 });
    s.ask("status").unwrap_err().0
}

#[test]
fn a_port_that_misbehaves_gets_a_timeout_naming_it_never_a_hang_or_a_false_reply() {
    // silence
    assert_eq!(against(b"", false), "--port /dev/fake: no reply to 'status' within 0.3 s");
    // endless blank lines
    assert!(against(b"\r\n\r\n\r\n\r\n", true).starts_with("--port /dev/fake: no reply to 'status' within"));
    // a line that is not the protocol: never printed as the reply
    let e = against(b"hello from a modem\r\n", false);
    assert!(e.contains("it sent 'hello from a modem': is this a polyturn board?"), "{e}");
    // endless bytes with no newline: bounded, refused
    assert!(against(b"xxxxxxxxxxxxxxxx", true).contains("longer than 512 bytes"));
    // an untagged `ok` (another program's, or noise) is not our reply
    assert!(against(b"ok ratio=3\r\n", false).contains("no reply"));
    // a firmware without tags answers a tagged command with this
    assert!(against(b"error: unknown command or wrong arguments (try help)\r\n", false)
        .contains("does not tag its replies"));
}

/// A port that echoes every byte it is sent, with a board behind it or not.
struct Echoing {
    board: Option<FakeDevice>,
    echo: std::collections::VecDeque<u8>,
}

impl Read for Echoing {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.echo.is_empty() {
            return self.board.as_mut().map_or(Err(ErrorKind::TimedOut.into()), |b| b.read(buf));
        }
        let n = buf.len().min(self.echo.len());
        for (b, e) in buf.iter_mut().zip(self.echo.drain(..n)) {
            *b = e;
        }
        Ok(n)
    }
}

impl Write for Echoing {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.echo.extend(data);
        self.board.as_mut().map_or(Ok(data.len()), |b| b.write(data))
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn the_echo_of_a_command_is_never_its_reply_and_the_boards_reply_behind_it_is() {
    let mut s = session(Echoing { board: None, echo: Default::default() });
    let e = s.ask("set cpr 1000").unwrap_err().0;
    assert!(e.starts_with("--port /dev/fake: no reply to 'set' within 0.3 s (the port echoed the command back"), "{e}");
    let mut s = session(Echoing { board: Some(FakeDevice::new()), echo: Default::default() });
    assert!(s.ask("set cpr 0").unwrap_err().0.starts_with("device: error: cpr"));
    assert_eq!(s.ask("set cpr 4000").unwrap(), "ok cpr=4000");
    assert_eq!(s.io.board.as_ref().unwrap().ctl.config().encoder_counts_per_rev, 4000);
}

#[test]
fn a_reply_is_ok_alone_ok_and_more_or_error_and_more_and_nothing_else() {
    use super::session::{is_reply, ok_or_device_error};
    for yes in ["ok", "ok cpr=4", "error: cpr 4..=1000000"] {
        assert!(is_reply(yes), "{yes}");
    }
    for no in ["", "okay", "ok\t1", " ok", "Ok", "error:x", "ERROR: x", " error: x", "error", "set cpr 1", "#1 ok"] {
        assert!(!is_reply(no), "{no}");
        assert!(ok_or_device_error(no.to_string()).is_err(), "{no}");
    }
    assert!(ok_or_device_error("error: x".into()).unwrap_err().0.starts_with("device: error: x"));
    assert_eq!(ok_or_device_error("ok".into()), Ok("ok".into()));
}

#[test]
fn a_command_that_reads_as_a_reply_is_not_sent() {
    let mut s = session(FakeDevice::new());
    assert!(s.ask("ok").unwrap_err().0.contains("reads as a reply"));
    assert!(s.ask("error: x").is_err());
    assert!(s.io.received.is_empty());
}

/// A port at its end: the board unplugged.
struct Gone;

impl Read for Gone {
    fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
        Ok(0)
    }
}

impl Write for Gone {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn a_port_that_ends_is_the_board_gone_not_a_timeout() {
    let e = session(Gone).ask("status").unwrap_err().0;
    assert!(e.starts_with("--port /dev/fake: the board closed the port before replying to 'status'"), "{e}");
}

#[test]
fn a_jog_out_of_the_consoles_range_is_refused_before_sending_whatever_the_port_says() {
    let mut s = session(FakeDevice::new());
    for deg in ["1e308", "inf", "-inf", "nan", "3600.001", "+90", ".5"] {
        let e = super::checks::jog(&mut s, deg).unwrap_err().0;
        assert!(e.starts_with("DEGREES must be -3600..=3600 degrees of the cutter"), "{deg}: {e}");
    }
    assert!(s.io.received.is_empty());
}

#[test]
fn the_console_is_found_among_the_ports_by_its_usb_ids() {
    use serialport::{SerialPortInfo, SerialPortType, UsbPortInfo};
    let usb = |name: &str, vid, pid| SerialPortInfo {
        port_name: name.into(),
        port_type: SerialPortType::UsbPort(UsbPortInfo {
            vid,
            pid,
            serial_number: None,
            manufacturer: None,
            product: None,
        }),
    };
    let ports = vec![
        usb("COM3", 0x0403, 0x6001), // an FTDI adapter
        SerialPortInfo { port_name: "COM1".into(), port_type: SerialPortType::Unknown },
        usb("COM7", 0x16c0, 0x27dd),
        usb("COM5", 0x16c0, 0x27dd),
    ];
    assert_eq!(super::port::first_console(ports), Some("COM5".into()));
    assert_eq!(super::port::first_console(vec![usb("COM3", 0x0403, 0x6001)]), None);
}

/// `device cam-off` sends the console's `cam off`, the way out of a table
/// made for one cutter (the board refuses another ratio under it).
#[test]
fn cam_off_is_the_consoles_cam_off() {
    let line = super::DeviceCommand::CamOff.line().unwrap();
    assert_eq!(line, "cam off");
    let mut s = session(FakeDevice::new());
    assert!(s.ask(&line).unwrap().starts_with("ok cam off"));
}
