use super::*;
use crate::{Config, Controller, Timing};
use std::format;
use std::string::String;
use std::vec::Vec;

fn lines(points: &[i32], crc_delta: u32) -> Vec<String> {
    let h = CamHeader {
        points: points.len() as u32,
        period_counts: 900,
        counts_per_rev: 2400,
        max_rate_hz: 9_600,
        max_accel: 1_600_000,
    };
    let mut out = std::vec![format!("begin {} 900 2400 9600 1600000", points.len())];
    for (i, chunk) in points.chunks(8).enumerate() {
        let vals: Vec<String> = chunk.iter().map(|v| format!("{v}")).collect();
        out.push(format!("data {} {}", i * 8, vals.join(" ")));
    }
    out.push(format!("end {:08x}", checksum(&h, points) ^ crc_delta));
    out
}

fn upload(u: &mut CamUpload, lines: &[String]) -> Result<Progress, &'static str> {
    let mut last = Err("nothing");
    for l in lines {
        last = u.line(l);
        last?;
    }
    last
}

#[test]
fn a_table_sent_in_chunks_with_its_checksum_arrives_whole_and_runs_in_the_core() {
    let points: Vec<i32> =
        (0..900).map(|i| ((i as f64 / 900.0 * core::f64::consts::TAU).sin() * 2000.0) as i32).collect();
    let mut u = std::boxed::Box::new(CamUpload::default());
    let done = upload(&mut u, &lines(&points, 0)).unwrap();
    let Progress::Complete(h) = done else { panic!("{done:?}") };
    let (h2, got) = u.table().unwrap();
    assert_eq!((h2, got), (h, &points[..]));
    let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
    ctl.fit_cam(&h, Vec::leak(got.to_vec())).unwrap();
    assert_eq!(ctl.x_axis().unwrap().cam.points(), &points[..]);
    // another encoder is refused, naming the setting
    let other = Config { encoder_counts_per_rev: 4000, ..Config::default() };
    ctl.set_config(other).unwrap();
    assert!(ctl.x_axis().is_none(), "a cam in counts of the old encoder comes off");
    assert!(ctl.fit_cam(&h, Vec::leak(points.clone())).unwrap_err().contains("cpr"));
}

#[test]
fn a_corrupted_chunk_or_checksum_discards_the_table() {
    let points: Vec<i32> = (0..64).collect();
    let mut u = std::boxed::Box::new(CamUpload::default());
    assert!(upload(&mut u, &lines(&points, 1)).unwrap_err().contains("checksum"));
    assert!(u.table().is_none());
    let mut bad = lines(&points, 0);
    bad[3] = bad[3].replacen(" 17 ", " 71 ", 1); // one value changed in transit
    assert!(upload(&mut u, &bad).unwrap_err().contains("checksum"));
    let mut skipped = lines(&points, 0);
    skipped.remove(2);
    assert!(upload(&mut u, &skipped).unwrap_err().contains("order"));
    assert!(u.line("data 0 1 2").unwrap_err().contains("cam begin first"), "an error ends the upload");
    assert!(u.line("begin 5000 9000 2400 1 1").unwrap_err().contains("2..=1024"));
}

#[test]
fn a_refused_line_abandons_the_upload_whole_and_says_so() {
    let points = [0, 1, 2, 3];
    let all = lines(&points, 0);
    let mut u = CamUpload::default();
    assert!(!u.in_progress());
    u.line(&all[0]).unwrap();
    assert!(u.in_progress());
    // two good values, then one that is not a number: the upload is gone
    // (the firmware's reply says so, from `in_progress` before the line)
    assert!(u.line("data 0 0 1 x").is_err());
    assert!(!u.in_progress() && u.table().is_none());
    assert!(upload(&mut u, &all[1..]).is_err(), "data without a begin is refused");
    assert!(matches!(upload(&mut u, &all), Ok(Progress::Complete(_))));
    assert!(!u.in_progress(), "complete is not in progress");
}

#[test]
fn a_number_with_a_sign_or_leading_zeros_is_refused_in_every_field() {
    let points: Vec<i32> = (-4..4).collect();
    let good = lines(&points, 0);
    let mut u = std::boxed::Box::new(CamUpload::default());
    assert!(matches!(upload(&mut u, &good), Ok(Progress::Complete(_))), "the well-formed table passes");
    for (at, from, to) in [
        (0, "begin 8", "begin +8"),
        (0, "begin 8 900", "begin 8 0900"),
        (0, "1600000", "+1600000"),
        (1, "data 0", "data +0"),
        (1, "data 0", "data 00"),
        (1, " 1 ", " +1 "),
        (1, " -1 ", " -01 "),
        (2, "end ", "end +"),
    ] {
        let mut bad = good.clone();
        bad[at] = bad[at].replacen(from, to, 1);
        assert_ne!(bad, good, "{to}: the line changed");
        let mut u = std::boxed::Box::new(CamUpload::default());
        assert!(upload(&mut u, &bad).is_err(), "{:?}", bad[at]);
        assert!(u.table().is_none());
    }
}

/// A refusal reads as its reason: the text, or the motion's figures (what
/// the console prints after `error: `).
#[test]
fn a_table_refusal_displays_its_reason() {
    assert_eq!(format!("{}", TableRefusal::Text("cam: no upload in progress")), "cam: no upload in progress");
    let m = motion::MotionError::Rate { span: 1, apart: 125, needs_hz: 20_000, max_hz: 9_600 };
    let shown = format!("{}", TableRefusal::Motion(m));
    assert_eq!(shown, format!("{m}"));
    assert!(shown.contains("125 steps apart need 20000 X steps/s"), "{shown}");
}
