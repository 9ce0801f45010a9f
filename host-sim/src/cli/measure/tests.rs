//! The stock and the cut as measured: a diameter is the same
//! stock as half its radius, an across-flats the same cut as its depth,
//! on every command that takes them, and exactly one of each is taken.

use crate::cli::dispatch;
use serde_json::Value;

fn run(line: &str) -> Result<String, String> {
    dispatch(&line.split_whitespace().map(String::from).collect::<Vec<_>>()).map_err(|e| e.0)
}

fn json(line: &str) -> Value {
    serde_json::from_str(&run(&format!("{line} --json")).unwrap()).unwrap()
}

const REST: &str = "--cutter-radius 50 --ratio 2:1 --edges 3 --direction same";

#[test]
fn a_stock_diameter_is_the_same_stock_as_half_its_radius_on_every_command() {
    for (cmd, tail) in
        [("geometry", ""), ("compensate", "--rpm 100 --x-max-speed 200 --x-max-accel 20000"), ("setups", "")]
    {
        let rest = if cmd == "setups" { "--sides 6 --cutter-radius 50" } else { REST };
        let by_radius = json(&format!("{cmd} {rest} --stock-radius 10 --depth 1.5 {tail}"));
        let mut by_diameter = json(&format!("{cmd} {rest} --stock-diameter 20 --depth 1.5 {tail}"));
        if cmd == "setups" {
            // the command lines echo the flag as given
            let echoed =
                by_diameter["geometry_command"].as_str().unwrap().replace("--stock-diameter 20", "--stock-radius 10");
            by_diameter["geometry_command"] = echoed.into();
            by_diameter["simulate_command"] = by_radius["simulate_command"].clone();
        }
        assert_eq!(by_radius, by_diameter, "{cmd}");
    }
}

#[test]
fn geometry_takes_across_flats_and_works_out_the_depth_as_setups_does() {
    let by_depth = json(&format!("geometry {REST} --stock-radius 10 --depth 1.5"));
    let by_af = json(&format!("geometry {REST} --stock-radius 10 --across-flats 17"));
    assert_eq!(by_depth, by_af);
    assert_eq!(by_af["across_flats"].as_f64().map(|v| (v - 17.0).abs() < 1e-6), Some(true));
    let setups = json("setups --sides 6 --stock-diameter 20 --across-flats 17 --cutter-radius 50");
    assert_eq!(setups["depth"], by_af["depth"]);
}

#[test]
fn an_across_flats_not_under_the_stock_diameter_is_refused_naming_it() {
    let e = run(&format!("geometry {REST} --stock-diameter 20 --across-flats 20")).unwrap_err();
    assert_eq!(e, "--across-flats must be at most the stock diameter (20 mm) less 0.002 mm: a depth of cut of at least 0.001 mm (got '20')");
    // nor one that leaves a depth --depth would refuse, in setups as in geometry
    for cmd in ["setups --sides 6", "geometry --cutter-radius 50 --ratio 2 --edges 3 --direction same"] {
        let e = run(&format!("{cmd} --stock-diameter 20 --across-flats 19.9999")).unwrap_err();
        assert!(e.starts_with("--across-flats must be at most the stock diameter (20 mm) less 0.002 mm"), "{cmd}: {e}");
    }
    // the bound itself is taken, whatever the float makes of 20 - 19.998
    for (d, af) in [("20", "19.998"), ("100", "99.998"), ("1000", "999.998")] {
        let e = run(&format!("setups --sides 6 --stock-diameter {d} --across-flats {af}")).err().unwrap_or_default();
        assert!(!e.starts_with("--across-flats"), "{d} {af}: {e}");
    }
    // a depth of 5 µm is one --depth takes: whatever else is said, not this
    let e = run(&format!("geometry {REST} --stock-diameter 20 --across-flats 19.99")).err().unwrap_or_default();
    assert!(!e.starts_with("--across-flats"), "{e}");
    let e = run(&format!("simulate {REST} --stock-radius 10 --across-flats 25 --rpm 300 --revolutions 1")).unwrap_err();
    assert!(e.starts_with("--across-flats "), "{e}");
    let e = run(&format!("geometry {REST} --stock-diameter 20 --depth 10")).unwrap_err();
    assert_eq!(e, "--depth must be > 0 and < the stock radius (10 mm) (got 10)");
}

#[test]
fn stock_too_thin_for_any_cut_is_refused_naming_the_stock_flag_given() {
    let tail = "--ratio 2 --edges 3 --direction same";
    for cmd in [
        "setups --sides 8".to_string(),
        format!("geometry --cutter-radius 50 {tail}"),
        format!("simulate --cutter-radius 50 {tail} --rpm 300 --revolutions 1"),
        format!("compensate --cutter-radius 50 {tail} --rpm 100 --x-max-speed 200 --x-max-accel 20000"),
    ] {
        for cut in ["--depth 0.001", "--across-flats 0.001"] {
            let e = run(&format!("{cmd} --stock-diameter 0.002 {cut}")).unwrap_err();
            assert_eq!(
                e,
                "--stock-diameter must be more than 0.002 mm for any cut: a depth of cut of at least 0.001 mm that leaves some stock (got 0.002)",
                "{cmd} {cut}"
            );
            let e = run(&format!("{cmd} --stock-radius 0.001 {cut}")).unwrap_err();
            assert_eq!(
                e,
                "--stock-radius must be more than 0.001 mm for any cut: a depth of cut of at least 0.001 mm that leaves some stock (got 0.001)",
                "{cmd} {cut}"
            );
        }
    }
    // the least stock that allows a cut is taken
    assert!(run("setups --sides 8 --stock-diameter 0.0021 --depth 0.001").is_ok());
}

#[test]
fn both_or_neither_of_a_pair_is_refused_in_one_sentence_naming_both() {
    let both = run(&format!("geometry {REST} --stock-radius 10 --stock-diameter 20 --depth 1")).unwrap_err();
    assert_eq!(both, "--stock-radius cannot be given with --stock-diameter: give one of them");
    let both = run(&format!("geometry {REST} --stock-radius 10 --depth 1 --across-flats 18")).unwrap_err();
    assert_eq!(both, "--depth cannot be given with --across-flats: give one of them");
    let neither = run(&format!("geometry {REST} --depth 1")).unwrap_err();
    assert_eq!(neither, "geometry needs --stock-radius (or --stock-diameter)");
    let neither = run("setups --sides 6 --stock-diameter 20").unwrap_err();
    assert_eq!(neither, "setups needs --depth (or --across-flats)");
}

#[test]
fn geometry_says_the_stock_diameter_and_the_across_corners_a_machinist_measures() {
    let text = run(&format!("geometry {REST} --stock-radius 10 --depth 1.5")).unwrap();
    let v = json(&format!("geometry {REST} --stock-radius 10 --depth 1.5"));
    let ac = 2.0 * v["circumscribed_radius"].as_f64().unwrap();
    assert_eq!(v["across_corners"].as_f64(), Some(ac));
    assert_eq!(v["stock_diameter"].as_f64(), Some(20.0));
    assert!(text.contains("stock diameter 20.0000 mm, depth 1.5000 mm, cutter radius 50.0000 mm"), "{text}");
    assert!(text.contains(&format!("across flats 17.0000 mm, across corners {ac:.4} mm")), "{text}");
    let sim = run(&format!("simulate {REST} --stock-diameter 20 --depth 1.5 --rpm 300 --revolutions 2")).unwrap();
    assert!(sim.contains("(stock diameter 20)") && sim.contains("across corners"), "{sim}");
}

#[test]
fn an_odd_section_has_no_across_corners_but_a_corner_to_flat() {
    let line = "geometry --cutter-radius 50 --stock-radius 10 --depth 1 --ratio 5:2 --edges 2 --direction same";
    let v = json(line);
    assert!(v["across_flats"].is_null() && v["across_corners"].is_null(), "{v}");
    let to_flat = v["inscribed_radius"].as_f64().unwrap() + v["circumscribed_radius"].as_f64().unwrap();
    let text = run(line).unwrap();
    assert!(text.contains(&format!("across flats n/a (odd sides), corner to opposite flat {to_flat:.4} mm")), "{text}");
}

#[test]
fn a_section_round_whatever_the_cutter_blames_the_ratio_not_the_cutter() {
    // at 1/1000 the cutter barely turns: its tip shaves a circle, and no
    // cutter would cut flats
    let e = run("geometry --cutter-radius 50 --stock-diameter 20 --depth 1 --ratio 1:1000 --edges 3 --direction same")
        .unwrap_err();
    assert!(
        e.starts_with("--ratio cuts a nearly round section with 3 edges with any cutter up to 100 x the stock radius (its flats bulge"),
        "{e}"
    );
    // a small cutter at a working ratio is still the cutter's fault
    let e = run("geometry --cutter-radius 3 --stock-radius 10 --depth 0.1 --ratio 5/3 --edges 12 --direction same")
        .unwrap_err();
    assert!(e.starts_with("--cutter-radius is too small for this depth"), "{e}");
}

#[test]
fn one_or_two_flats_must_stand_out_from_the_round() {
    // a circle has no chord for one or two "flats" to bulge from: a cutter
    // that barely turns shaves the bar round, 1.1 µm from corner to flat
    for edges in [1, 2] {
        let line = format!(
            "geometry --cutter-radius 40 --stock-radius 10 --depth 1 --direction opposite --ratio 1:1000 --edges {edges}"
        );
        let e = run(&line).unwrap_err();
        assert!(
            e.contains("nearly round (its flats stand 0.0011 mm below its corners, under half the 1 mm depth)"),
            "{e}"
        );
    }
    // one flat a lathe turn, a D: 1 mm from corner to flat, all the depth
    assert!(run("geometry --cutter-radius 40 --stock-radius 10 --depth 1 --direction opposite --ratio 1:2 --edges 2")
        .is_ok());
}

#[test]
fn setups_lists_only_what_geometry_takes() {
    let rows = json("setups --sides 6 --stock-radius 10 --depth 1 --cutter-radius 2.001");
    let rows = rows["setups"].as_array().expect("setups");
    assert!(!rows.is_empty());
    for r in rows {
        let line = format!(
            "geometry --cutter-radius 2.001 --stock-radius 10 --depth 1 --ratio {} --edges {} --direction {}",
            r["ratio"].as_str().unwrap(),
            r["edges"],
            r["direction"].as_str().unwrap()
        );
        assert!(run(&line).is_ok(), "{line}: {:?}", run(&line));
    }
    let text = run("setups --sides 6 --stock-radius 10 --depth 1 --cutter-radius 2.001").unwrap();
    assert!(text.contains(&format!("{} setups for 6 sides", rows.len())), "{text}");
    assert!(
        text.contains("5 more left out: with this cutter their section is nearly round, and geometry refuses them"),
        "{text}"
    );
}
