//! A cam table file is checked before the port opens: what it declares,
//! and its points by the board's own rules.

use super::*;
use crate::noncircular::path::Polygon;
use crate::noncircular::plan::{plan, Axis, Outcome};

/// `polyturn cam --sides 8 --inscribed-radius 20 --rpm 12 --x-max-speed 12
/// --x-max-accel 2000`'s table, at 800 steps/mm.
fn octagon() -> CamFile {
    let axis = Axis { rpm: 12.0, max_speed: 12.0, max_accel: 2000.0 };
    let Outcome::Sharp(path, _) = plan(Polygon { sides: 8, apothem_mm: 20.0 }, 3, axis) else { panic!("sharp") };
    crate::noncircular::table::build(&path, 2400, 800.0, (9_600, 1_600_000))
}

fn checked(t: &CamFile) -> Result<CamFile, String> {
    cam_table("t.json", &serde_json::to_string(t).unwrap()).map_err(|e| e.0)
}

#[test]
fn a_table_polyturn_cam_makes_is_taken() {
    let t = octagon();
    assert_eq!(checked(&t), Ok(t));
}

#[test]
fn steps_per_mm_outside_polyturn_cams_range_is_refused_naming_it() {
    for (spm, shown) in [(0.0, "0.0"), (-800.0, "-800.0"), (1e308, "1e308"), (0.5, "0.5"), (100_001.0, "100001.0")] {
        let e = checked(&CamFile { steps_per_mm: spm, ..octagon() }).unwrap_err();
        assert_eq!(
            e,
            format!("upload-cam: 't.json' is refused: steps_per_mm must be a finite number >= 1 and <= 100000 (got {shown})")
        );
    }
    // the JSON text itself, as a hand-edited file has it
    let text = serde_json::to_string(&octagon()).unwrap().replace("\"steps_per_mm\":800.0", "\"steps_per_mm\":1e308");
    assert!(cam_table("t.json", &text).unwrap_err().0.contains("steps_per_mm must be"));
}

/// 125 mm between neighbours at 800 steps/mm: refused with the board's own
/// figures (`cam_upload::motion`), before anything is sent.
#[test]
fn a_jump_no_x_axis_can_make_is_refused_with_the_boards_figures() {
    let mut t = octagon();
    t.points[100] += 100_000;
    let h = t.header();
    let core = polyturn_sync::controller::check_table(&h, &t.points).unwrap_err().to_string();
    assert!(core.starts_with("cam table: neighbouring points 10"), "{core}");
    assert_eq!(checked(&t).unwrap_err(), format!("upload-cam: 't.json' is refused: {core}"));
}

/// Points the board's arithmetic cannot interpolate between (2^23 steps
/// apart or more) are named with their values, the wrap from the last to
/// the first too.
#[test]
fn neighbouring_points_too_far_apart_are_named_with_their_values() {
    let mut t = octagon();
    t.points[7] = i32::MIN;
    assert_eq!(
        checked(&t).unwrap_err(),
        format!(
            "upload-cam: 't.json' is refused: points[6] and points[7] must be less than 8388608 (2^23) steps apart, the board's interpolation's range (got {} and -2147483648)",
            t.points[6]
        )
    );
    // each step 4 200 000, the wrap back 8 400 000
    let t = CamFile { points: vec![0, 4_200_000, 8_400_000], ..octagon() };
    let e = checked(&t).unwrap_err();
    assert!(e.contains("points[2] and points[0] must be less than 8388608 (2^23) steps apart"), "{e}");
    assert!(e.contains("the table repeats") && e.ends_with("(got 8400000 and 0)"), "{e}");
}

#[test]
fn an_encoder_or_an_x_axis_the_board_refuses_is_refused_here() {
    let e = checked(&CamFile { counts_per_rev: 0, ..octagon() }).unwrap_err();
    assert_eq!(
        e,
        "upload-cam: 't.json' is refused: counts_per_rev must be 4..=1000000 counts per lathe rev (the console's cpr; got 0)"
    );
}

/// The X axis, the period and the points a table declares are refused
/// naming the table's own field and its range, not the console's words.
#[test]
fn an_x_axis_a_period_or_a_point_count_the_board_refuses_is_named_by_its_field() {
    let refused =
        |t: CamFile| checked(&t).unwrap_err().trim_start_matches("upload-cam: 't.json' is refused: ").to_string();
    let top = polyturn_sync::cam_upload::X_MAX_RATE_HZ;
    for rate in [0, top + 1] {
        assert_eq!(
            refused(CamFile { max_rate_hz: rate, ..octagon() }),
            format!(
                "max_rate_hz must be 1..={top} steps/s: the board emits at most one X step per two ticks (got {rate})"
            )
        );
    }
    assert_eq!(
        refused(CamFile { max_accel: 0, ..octagon() }),
        format!("max_accel must be 1..={} steps/s^2 (got 0)", u32::MAX)
    );
    let n = octagon().points.len();
    assert_eq!(
        refused(CamFile { period_counts: n as u32 - 1, ..octagon() }),
        format!(
            "period_counts must be {n}..={} lathe counts: at least one for each of the {n} points (got {})",
            u32::MAX,
            n - 1
        )
    );
    for points in [vec![5], vec![0; 1025]] {
        let got = points.len();
        assert_eq!(
            refused(CamFile { points, period_counts: 2400, ..octagon() }),
            format!("points must hold 2..=1024 values (got {got})")
        );
    }
}

/// A compensating table's cutter is one a board could be set to, and the
/// file has no field polyturn does not write: refused before any port.
#[test]
fn a_cutter_no_board_takes_or_an_unknown_field_is_refused_naming_it() {
    use crate::noncircular::table::MadeFor;
    let with = |ratio: &str, edges: u32| CamFile {
        cutter: Some(MadeFor { ratio: ratio.into(), edges, direction: None }),
        ..octagon()
    };
    // 8/3 x 3: 8 passes a turn, 300 counts each, the octagon's 900 three
    assert!(checked(&with("8/3", 3)).is_ok());
    // a ratio the board takes only with other settings is still a ratio
    assert!(checked(&with("1000", 12)).is_ok());
    for ratio in ["garbage", "0", "-3", "NaN"] {
        let e = checked(&with(ratio, 2)).unwrap_err();
        assert!(e.starts_with("upload-cam: 't.json' is refused: cutter.ratio "), "{ratio}: {e}");
        assert!(e.ends_with(&format!("(got '{ratio}')")), "{e}");
    }
    for edges in [0, 99_999] {
        let e = checked(&with("2", edges)).unwrap_err();
        assert_eq!(e, format!("upload-cam: 't.json' is refused: cutter.edges must be 1..=12 (got {edges})"));
    }
    let text = serde_json::to_string(&octagon()).unwrap().replace("{\"format\"", "{\"bogus\":1,\"format\"");
    let e = cam_table("t.json", &text).unwrap_err().0;
    assert!(e.contains("unknown field `bogus`"), "{e}");
}

/// A compensating table's sense is one the board's `dir` takes, refused
/// naming the field and the two it may be.
#[test]
fn a_cutter_sense_no_board_takes_is_refused_naming_the_field() {
    let with = |direction: &str| {
        let cutter = format!(r#""cutter":{{"ratio":"8/3","edges":3,"direction":"{direction}"}},"points""#);
        serde_json::to_string(&octagon()).unwrap().replacen(r#""points""#, &cutter, 1)
    };
    let e = cam_table("t.json", &with("sideways")).unwrap_err().0;
    let want = "upload-cam: 't.json' is not a polyturn cam table: cutter.direction: unknown variant `sideways`, expected `same` or `opposite`";
    assert!(e.starts_with(want), "{e}");
    let t = cam_table("t.json", &with("opposite")).unwrap();
    assert_eq!(serde_json::to_value(&t.cutter).unwrap()["direction"], "opposite");
}

/// A compensating table's period is a whole number of its cutter's
/// passes: else its X motion slips against the cutter a little each pass.
#[test]
fn a_period_that_is_no_whole_number_of_the_cutters_passes_is_refused() {
    use crate::noncircular::table::MadeFor;
    let with = |ratio: &str, edges: u32, period_counts: u32| CamFile {
        cutter: Some(MadeFor { ratio: ratio.into(), edges, direction: None }),
        period_counts,
        ..octagon()
    };
    // 5/2 x 2: 5 passes a turn, 480 counts each: the octagon's 900 is not
    let e = checked(&with("5/2", 2, 900)).unwrap_err();
    assert_eq!(
        e,
        "upload-cam: 't.json' is refused: period_counts must be a whole number of the cutter's passes, a multiple of 480 counts for ratio 5/2 with 2 edges at 2400 counts a turn (got 900)"
    );
    // 11/3 x 3: 11 passes over a turn of 2400 counts, no whole count each:
    // only the whole turn repeats
    assert!(checked(&with("11/3", 3, 900)).unwrap_err().contains("a multiple of 2400 counts"));
    let e = checked(&with("2", 3, 401)).unwrap_err();
    assert!(e.contains("a multiple of 400 counts") && e.ends_with("(got 401)"), "{e}");
}

/// A hand-edited number too large for its field is named by the field.
#[test]
fn a_number_out_of_its_fields_type_is_named_by_its_field() {
    let text = serde_json::to_string(&octagon()).unwrap();
    let cases = [
        (
            text.replacen("\"max_accel\":1600000", "\"max_accel\":1000000000000000", 1),
            "max_accel: invalid value: integer `1000000000000000`, expected u32",
        ),
        (
            text.replacen("\"points\":[", "\"points\":[1e20,", 1),
            "points[0]: invalid type: floating point `1e+20`, expected i32",
        ),
    ];
    for (t, want) in cases {
        let e = cam_table("t.json", &t).unwrap_err().0;
        assert!(e.starts_with(&format!("upload-cam: 't.json' is not a polyturn cam table: {want}")), "{e}");
    }
}

/// A file is one table: a second pasted after it, or any text, is refused
/// (the first would be sent and the rest silently left); white space
/// after it, as an editor leaves, is taken.
#[test]
fn anything_after_the_table_is_refused_and_trailing_white_space_taken() {
    let one = serde_json::to_string(&octagon()).unwrap();
    for tail in [one.as_str(), "xyz", "{}", "0"] {
        let e = cam_table("t.json", &format!("{one}\n{tail}")).unwrap_err().0;
        assert!(
            e.starts_with("upload-cam: 't.json' is not a polyturn cam table: it holds more after the table ("),
            "{e}"
        );
    }
    assert_eq!(cam_table("t.json", &format!("{one}\n \t\r\n")).map_err(|e| e.0), Ok(octagon()));
}

/// An X axis declared far slower than the table's own path, though each
/// point is within a step of its neighbour: refused with the figure the
/// spans of the path need.
#[test]
fn a_table_declaring_an_axis_slower_than_its_path_is_refused() {
    let t = CamFile { max_accel: 1, ..octagon() };
    let e = checked(&t).unwrap_err();
    assert!(e.starts_with("upload-cam: 't.json' is refused: cam table: a bend of "), "{e}");
    assert!(e.contains("beyond its max-accel 1 steps/s^2"), "{e}");
    let e = checked(&CamFile { max_rate_hz: 1, ..octagon() }).unwrap_err();
    assert!(e.contains("apart move ") && e.contains("beyond its max-rate 1 steps/s"), "{e}");
}
