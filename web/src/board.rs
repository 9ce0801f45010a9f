//! The fake serial port the page's device panel is tested against: the
//! real sync core's console and controller behind the firmware's framing
//! (`polyturn_bench::fakeboard`), time passing on a machine model between
//! commands and while `watch` streams.

use polyturn_bench::fakeboard::{ticks_in_ms, FakeDevice, Workshop};
use std::io::Write;
use wasm_bindgen::prelude::*;

/// Control ticks that pass before each command: 10 ms.
const TICKS_PER_LINE: usize = ticks_in_ms(10);

#[wasm_bindgen]
pub struct FakeBoard {
    dev: FakeDevice,
}

impl Default for FakeBoard {
    fn default() -> FakeBoard {
        FakeBoard::new()
    }
}

#[wasm_bindgen]
impl FakeBoard {
    /// A board just started with the default settings, its lathe at rest
    /// but for the encoder check (`check-encoder stop` turns it first).
    #[wasm_bindgen(constructor)]
    pub fn new() -> FakeBoard {
        let mut dev = FakeDevice::new();
        let mut workshop = Workshop::new(TICKS_PER_LINE);
        workshop.turn_for_check = true;
        dev.workshop = Some(workshop);
        FakeBoard { dev }
    }

    /// Bytes from the host (what WebSerial's writer sends).
    pub fn write(&mut self, data: &[u8]) {
        let _ = self.dev.write(data);
    }

    /// The replies the board has sent since the last read.
    pub fn read(&mut self) -> Vec<u8> {
        self.dev.take_replies()
    }

    /// While `watch` runs, its next status line (a tenth of a second
    /// passes on the machine); empty otherwise. The port calls it at 10 Hz.
    pub fn watch_line(&mut self) -> Vec<u8> {
        self.dev.watch_line()
    }

    /// The lathe's speed when it turns by hand, counts/s
    /// (`Workshop::turn_at`), and the time that passes before each
    /// command, ms (the encoder check needs 1.2 s of rest and a turn).
    pub fn set_machine(&mut self, counts_per_s: u32, ms_per_line: u32) {
        if let Some(m) = &mut self.dev.workshop {
            m.turn_at(counts_per_s);
            m.ticks_per_line = ticks_in_ms(u64::from(ms_per_line));
        }
    }

    /// The simulated lathe's speed, rpm (0 stops it): it ramps there on the
    /// simulator's spindle model and turns the board's encoder.
    pub fn set_lathe_rpm(&mut self, rpm: f64) {
        if let Some(m) = &mut self.dev.workshop {
            m.set_lathe_rpm(rpm);
        }
    }

    /// The machinist turns the chuck by hand by `degrees` (either way), at
    /// a hand's pace, as the board's time passes (`Workshop::turn_by_hand`):
    /// to the nearest count of the simulated lathe's encoder.
    pub fn turn_by_hand(&mut self, degrees: f64) {
        if let Some(m) = &mut self.dev.workshop {
            let counts = (degrees.clamp(-36_000.0, 36_000.0) * m.cpr as f64 / 360.0).round() as i64;
            m.turn_by_hand(counts);
        }
    }

    /// Every command line the board received, in order.
    pub fn received(&self) -> Vec<String> {
        self.dev.received.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fake_board_answers_tagged_lines_as_the_firmware_does() {
        let mut b = FakeBoard::new();
        b.write(b"#7 set cpr 0\r\n#8 get cpr\r\n");
        let out = String::from_utf8(b.read()).unwrap();
        let lines: Vec<&str> = out.split("\r\n").collect();
        assert!(lines[0].starts_with("#7 error: cpr"), "{out}");
        assert_eq!(lines[1], "#8 ok cpr=2400");
        assert_eq!(b.received(), vec!["#7 set cpr 0", "#8 get cpr"]);
    }

    #[test]
    fn a_lathe_speed_set_turns_the_encoder_the_status_reads() {
        let mut b = FakeBoard::new();
        b.set_lathe_rpm(300.0);
        b.write(b"watch\n");
        b.read();
        let rpm = |line: Vec<u8>| -> f64 {
            let l = String::from_utf8(line).unwrap();
            l.split_whitespace().find_map(|kv| kv.strip_prefix("lathe_rpm=")).unwrap().parse().unwrap()
        };
        let lines: Vec<f64> = (0..15).map(|_| rpm(b.watch_line())).collect();
        assert!(lines[0] > 0.0 && (lines[14] - 300.0).abs() < 1.0, "{lines:?}");
    }

    #[test]
    fn a_hand_turns_the_chuck_by_degrees_and_the_board_reads_its_angle() {
        let mut b = FakeBoard::new();
        b.turn_by_hand(60.75); // 405 counts: past the index at count 5, to 60 degrees from it
        b.write(b"watch\n");
        b.read();
        let angle = |line: Vec<u8>| {
            String::from_utf8(line)
                .unwrap()
                .split_whitespace()
                .find_map(|kv| kv.strip_prefix("angle_deg=").map(String::from))
                .unwrap()
        };
        let lines: Vec<String> = (0..10).map(|_| angle(b.watch_line())).collect();
        assert_eq!(lines[9], "60.0", "{lines:?}");
        assert_ne!(lines[0], "60.0", "at a hand's pace: {lines:?}");
    }

    #[test]
    fn watch_streams_real_status_lines_until_the_next_command() {
        let mut b = FakeBoard::new();
        b.write(b"watch\n");
        let reply = String::from_utf8(b.read()).unwrap();
        let status = String::from_utf8(b.watch_line()).unwrap();
        assert!(reply.starts_with("ok") && status.starts_with("ok state=idle fault=none"), "{reply} / {status}");
        assert!(b.read().is_empty(), "nothing more until a command");
        b.write(b"#1 get ratio\n");
        assert_eq!(String::from_utf8(b.read()).unwrap(), "#1 ok ratio=2\r\n");
        assert!(b.watch_line().is_empty(), "a command ends the watch");
    }
}
