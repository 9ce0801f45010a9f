//! The committed seeds (`corpus/<target>/seed-*`) and regression inputs
//! (`regressions/<target>/`), made from the code they exercise:
//!
//! ```text
//! cargo test --test seeds -- --ignored   # (re)writes them
//! cargo test --test seeds                # checks they are current
//! ```
//! The settings seeds are records `codec::encode` wrote (so the fuzzer
//! starts past the CRC); the regressions are inputs that once found a bug.

use polyturn_sync::cam_upload::{checksum, CamHeader};
use polyturn_sync::codec::{self, DecodeError};
use polyturn_sync::Config;
use std::path::PathBuf;

fn config(changes: &[(&str, &str)]) -> Config {
    changes.iter().fold(Config::default(), |c, (name, value)| c.with(name, value).unwrap())
}

/// A record with the ratio's terms as written (unreduced), CRC valid.
fn with_ratio_terms(p: u16, q: u16) -> Vec<u8> {
    let mut b = codec::encode(&Config::default());
    b[11..13].copy_from_slice(&p.to_le_bytes());
    b[13..15].copy_from_slice(&q.to_le_bytes());
    let crc = codec::crc32(&b[..codec::LEN - 4]);
    b[codec::LEN - 4..].copy_from_slice(&crc.to_le_bytes());
    b.to_vec()
}

/// The record body the fuzzer found (cpr 352, ratio 2/2, bldc, ...).
const FOUND_2_2: [u8; 45] = [
    80, 84, 1, 96, 1, 0, 0, 128, 12, 0, 0, 2, 0, 2, 0, 1, 3, 64, 13, 3, 0, 128, 26, 6, 0, 64, 0, 0, 0, 0, 0, 0, 0, 1,
    1, 136, 19, 0, 0, 208, 7, 0, 0, 220, 5,
];

/// `body` with its CRC-32 appended.
fn sealed(body: [u8; codec::LEN - 4]) -> Vec<u8> {
    let mut b = body.to_vec();
    b.extend_from_slice(&codec::crc32(&body).to_le_bytes());
    b
}

/// A `cam` upload of `points` with its real checksum.
fn cam_upload(points: &[i32], period: u32) -> String {
    let h = CamHeader {
        points: points.len() as u32,
        period_counts: period,
        counts_per_rev: 2400,
        max_rate_hz: 9_600,
        max_accel: 1_600_000,
    };
    let mut out = format!("cam begin {} {period} 2400 9600 1600000\n", points.len());
    for (i, chunk) in points.chunks(8).enumerate() {
        let vals: Vec<String> = chunk.iter().map(|v| v.to_string()).collect();
        out += &format!("cam data {} {}\n", i * 8, vals.join(" "));
    }
    out + &format!("cam end {:08x}\n", checksum(&h, points))
}

/// (path under fuzz/, contents)
fn files() -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = Vec::new();
    let mut add = |path: &str, bytes: &[u8]| out.push((path.to_string(), bytes.to_vec()));

    let records = [
        ("default", config(&[])),
        ("ratio-11-3", config(&[("max-rpm", "600"), ("ratio", "11/3"), ("phase", "-7.25")])),
        ("bldc-opposite", config(&[("drive", "bldc"), ("dir", "opposite"), ("enable", "high"), ("ratio", "3/2")])),
        ("none", config(&[("drive", "none"), ("edges", "1"), ("phase", "360")])),
        (
            "extremes",
            config(&[
                ("steps", "1"),
                ("cpr", "1000000"),
                ("edges", "12"),
                ("pulse", "100"),
                ("max-rate", "250000"),
                ("ratio", "1/1000"),
                ("max-rpm", "10000"),
                ("dir-setup", "0"),
                ("ferror", "1000000"),
            ]),
        ),
    ];
    for (name, c) in records {
        add(&format!("corpus/settings/seed-{name}"), &codec::encode(&c));
    }
    // the `decoding_is_one_to_one` promise: an unreduced ratio decodes to
    // 2/1 and would re-encode to other bytes (DecodeError::NonCanonical)
    add("regressions/settings/unreduced-ratio-4-2", &with_ratio_terms(4, 2));
    add("regressions/settings/unreduced-ratio-2-8", &with_ratio_terms(2, 8));
    // what the `settings` target found from the seeds above in under a
    // second without the fix (ratio 2/2 among other changes), CRC made valid
    add("regressions/settings/fuzzer-ratio-2-2", &sealed(FOUND_2_2));

    add(
        "corpus/console/seed-commands",
        b"help\nget\nget ratio\nset ratio 11/3\nset phase -7.25\nengage\nstatus\nstop\nclear\nsave\ndefaults\n",
    );
    add(
        "corpus/console/seed-errors",
        b"set ratio 0\nset cpr 3\nset steps 8000000\nset\nfoo bar\n\xff\xfe\nset phase 400\n",
    );

    add("corpus/line_framing/seed-endings", b"status\r\nset ratio 2\rengage\n\n\r\r\nstop");
    let mut long = vec![b'x'; 96];
    long.extend_from_slice(b"\n");
    long.extend(vec![b'y'; 97]);
    long.extend_from_slice(b"\r\nstatus\n");
    add("corpus/line_framing/seed-bound", &long);

    let sine: Vec<i32> = (0..64).map(|i| ((i as f64 / 64.0 * std::f64::consts::TAU).sin() * 400.0) as i32).collect();
    add(
        "corpus/cam_upload/seed-sine",
        (cam_upload(&sine, 2400) + "engage\ntick 500 1\nstop\ntick 3000 0\n").as_bytes(),
    );
    add(
        "corpus/cam_upload/seed-star",
        b"cam begin 4 8 2400 9600 1600000\ncam data 0 0 8388607\ncam data 2 0 -100\ncam end *\ncam off\n",
    );
    add(
        "corpus/cam_upload/seed-other-cpr",
        b"set cpr 4000\ncam begin 2 2 2400 9600 1\ncam data 0 1 2\ncam end *\nset cpr 2400\ncam end *\n",
    );

    // (1 count a tick is 500 rpm on the default 2400-count encoder at 20 kHz)
    // found a harness bug (it took a table for gone after `cam data 2`
    // with no values, which the upload accepts and keeps the table)
    add(
        "regressions/cam_upload/data-after-end",
        b"cam begin 2 2 2400 9600 1\ncam data 0 1 2\ncam end *\ncam data 2\ncam end *\n",
    );

    add("corpus/tick/seed-run", b"set max-accel 50000000\nengage\ntick 400 1\nstatus\nset phase 12.5\ntick 200 1\nstop\ntick 300 1\ntick 3000 0\nsave\n");
    add("corpus/tick/seed-estop", b"set max-accel 50000000\nengage\ntick 200 1\nestop 1\ntick 10 1\nclear\nengage\nestop 0\nclear\nengage\ntick 100 1\nalarm 1\ntick 2 1\nalarm 0\nclear\ntick 5 0\n");
    add(
        "corpus/tick/seed-bldc",
        b"set drive bldc\nset max-accel 50000000\nengage\ntick 500 1\nslip 50\ntick 100 1\nstop\ntick 6000 0\n",
    );
    add("corpus/tick/seed-step-output", b"late 1\nset max-accel 50000000\nengage\ntick 100 1\nglitch 3\ntick 10 1\nclear\ntick 5 0\nengage\ntick 10 0\n");
    add("corpus/tick/seed-xcam", b"xcam 10000 100000 2400 0 100 200 100\nset max-accel 50000000\nengage\ntick 2000 1\nset phase 90\nstop\ntick 500 0\nxoff\n");
    add("corpus/tick/seed-stall", b"engage\ntick 50 1\nstop\ntick 200 0\nstall\ntick 1 30000\nunstall\nindex 5\ntick 10 1\nservice\nset drive none\nengage\ntick 20 1\n");
    add(
        "corpus/tick/seed-fast",
        b"set ratio 5/2\nengage\ntick 100 3\nset ratio 2\ntick 1 400\nclear\ntick 3000 0\nclear\n",
    );
    out
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
#[ignore = "writes the seed files: run with --ignored after a codec change"]
fn write() {
    for (path, bytes) in files() {
        let p = root().join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }
}

#[test]
fn the_committed_seeds_are_current() {
    for (path, bytes) in files() {
        let on_disk = std::fs::read(root().join(&path)).unwrap_or_default();
        assert!(on_disk == bytes, "{path} is stale: cargo test --test seeds -- --ignored");
    }
}

#[test]
fn the_settings_seeds_decode_and_the_regressions_are_refused() {
    for (path, bytes) in files() {
        if path.starts_with("corpus/settings/") {
            let c = codec::decode(&bytes).unwrap();
            assert_eq!(&codec::encode(&c)[..], &bytes[..]);
        }
    }
    assert_eq!(codec::decode(&with_ratio_terms(4, 2)), Err(DecodeError::NonCanonical("ratio")));
    assert_eq!(codec::decode(&with_ratio_terms(2, 8)), Err(DecodeError::NonCanonical("ratio")));
    assert_eq!(codec::decode(&sealed(FOUND_2_2)), Err(DecodeError::NonCanonical("ratio")));
}
