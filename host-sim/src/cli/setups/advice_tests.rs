//! `setups` warns of figures no lathe here can take:
//! tip speeds, cutter speeds and cutters past what a lathe swings, each a
//! `warning:` line with exit 0, and each row's own in the JSON.

use super::advice::{default_max_cutter_rpm, MAX_CUTTER_RADIUS_MM};
use super::tests::{json, run};

/// The planner run: 3000 rpm on 40 mm stock.
const FAST: &str = "setups --sides 6 --stock-diameter 40 --depth 3 --rpm 3000";

#[test]
fn tip_speeds_above_the_ceiling_are_warned_of_and_the_ceiling_is_a_flag() {
    let text = run(FAST).unwrap();
    assert!(
        text.contains(
            "\nwarning: 12 of 12 setups cut faster than --max-tip-speed 20 m/s at --rpm 3000 (up to 193.84 m/s)"
        ),
        "{text}"
    );
    assert!(!run(&format!("{FAST} --max-tip-speed 200")).unwrap().contains("--max-tip-speed"));
    // just above a row's tip speed warns of it, at it does not
    let v = json(FAST);
    let slowest =
        v["setups"].as_array().unwrap().iter().map(|r| r["peak_tip_speed"].as_f64().unwrap()).fold(f64::MAX, f64::min);
    let at = json(&format!("{FAST} --max-tip-speed {slowest}"));
    assert!(at["warnings"][0].as_str().unwrap().starts_with("11 of 12 setups cut faster"), "{at}");
    assert!(run("setups --sides 6 --stock-diameter 40 --depth 3 --rpm 300")
        .unwrap()
        .lines()
        .all(|l| !l.contains("tip speed")));
}

#[test]
fn cutter_speeds_above_the_default_motors_top_speed_are_warned_of() {
    assert_eq!(default_max_cutter_rpm(), 3750.0, "200000 steps/s over 3200 steps a turn");
    let text = run(FAST).unwrap();
    assert!(text.contains("\nwarning: 8 of 12 setups turn the cutter faster than --max-cutter-rpm 3750 at --rpm 3000 (up to 18000 rpm)"), "{text}");
    let v = json(&format!("{FAST} --max-cutter-rpm 18000"));
    assert!(v["warnings"].as_array().unwrap().iter().all(|w| !w.as_str().unwrap().contains("--max-cutter-rpm")), "{v}");
    let row = &json(FAST)["setups"][1];
    assert_eq!(row["cutter_rpm"].as_f64(), Some(9000.0));
    assert!(
        row["warnings"].as_array().unwrap().iter().any(|w| w == "cutter speed 9000 rpm is above --max-cutter-rpm 3750"),
        "{row}"
    );
}

#[test]
fn a_smallest_cutter_no_lathe_swings_is_warned_of_not_shown_as_a_setup() {
    let v = json(FAST);
    let big: Vec<f64> =
        v["setups"].as_array().unwrap().iter().filter_map(|r| r["min_cutter_radius"].as_f64()).collect();
    assert!(big.iter().any(|&r| r > MAX_CUTTER_RADIUS_MM) && big.iter().any(|&r| r <= MAX_CUTTER_RADIUS_MM), "{big:?}");
    let text = run(FAST).unwrap();
    assert!(text.contains("\nwarning: 1 of 12 setups need a cutter radius over 250 mm for --tolerance 0.01 mm (up to 1610 mm in min R1)"), "{text}");
    let row = &v["setups"][2];
    assert!(
        row["warnings"].to_string().contains("smallest cutter radius 1610 mm is more than a lathe swings"),
        "{row}"
    );
    assert!(v["setups"][0]["warnings"].to_string().contains("tip speed"), "the first row is within the swing");
    assert!(!v["setups"][0]["warnings"].to_string().contains("smallest cutter"));
}

#[test]
fn an_assumed_cutter_no_lathe_swings_is_warned_of_and_a_given_one_is_not() {
    let over =
        |stock: &str| json(&format!("setups --sides 6 --stock-diameter {stock} --depth 2"))["warnings"].to_string();
    assert!(
        over("101").contains("the assumed cutter radius 252.5 mm is more than a lathe swings (250 mm)"),
        "{}",
        over("101")
    );
    assert!(!over("100").contains("assumed cutter"), "5 x 50 mm is 250 mm: within");
    let given = json("setups --sides 6 --stock-diameter 101 --depth 2 --cutter-radius 100");
    assert!(!given["warnings"].to_string().contains("assumed cutter"), "{given}");
}
