//! Every figure `setups` prints for a row is one `geometry` gives for the
//! same setup: the flat deviation and corners at the row's cutter, and, at
//! the smallest cutter it recommends, a section `geometry` takes with
//! flats within `--tolerance`.

use super::tests::{json, run};
use serde_json::Value;

/// `--stock-…` and `--depth`/`--across-flats` as given in `line`.
fn stock_and_cut(line: &str) -> String {
    let given = line.split_whitespace().collect::<Vec<_>>();
    let flag = |name: &str| given.iter().position(|w| *w == name).map(|i| format!("{name} {}", given[i + 1]));
    let stock = flag("--stock-radius").or(flag("--stock-diameter")).unwrap();
    let cut = flag("--depth").or(flag("--across-flats")).unwrap();
    format!("{stock} {cut}")
}

/// `geometry --json` for `row` with cutter radius `r1` (as typed).
fn geometry(line: &str, row: &Value, r1: &str) -> Result<Value, String> {
    let g = format!(
        "geometry --cutter-radius {r1} {} --ratio {} --edges {} --direction {}",
        stock_and_cut(line),
        row["ratio"].as_str().unwrap(),
        row["edges"],
        row["direction"].as_str().unwrap()
    );
    run(&format!("{g} --json")).map(|s| serde_json::from_str(&s).unwrap()).map_err(|e| format!("{g}: {e}"))
}

/// Each row whose figures `geometry` does not give, said.
fn rows_unlike_geometry(line: &str) -> Vec<String> {
    let v = json(line);
    // as printed in the first row's line: the JSON reader's float may be
    // a unit in the last place off the figure printed
    let Some(first) = v["geometry_command"].as_str() else { return Vec::new() }; // no rows
    let first = first.split_whitespace().collect::<Vec<_>>();
    let r1 = first[first.iter().position(|w| *w == "--cutter-radius").unwrap() + 1];
    let mut bad = Vec::new();
    for row in v["setups"].as_array().unwrap() {
        match geometry(line, row, r1) {
            Ok(g) if g["flat_deviation"] == row["flat_deviation"] && g["corners_sharp"] == row["corners_sharp"] => {}
            Ok(g) => bad.push(format!("{row}: geometry {} {}", g["flat_deviation"], g["corners_sharp"])),
            Err(e) => bad.push(e),
        }
    }
    bad
}

/// Each row's recommended cutter that `geometry` refuses or finds out of
/// `tol`, said.
fn smallest_cutters_out_of_tolerance(line: &str, tol: f64) -> Vec<String> {
    let v = json(line);
    let mut bad = Vec::new();
    for row in v["setups"].as_array().unwrap() {
        let Some(r) = row["min_cutter_radius"].as_f64() else { continue };
        match geometry(line, row, &r.to_string()) {
            Ok(g) if g["flat_deviation"].as_f64().is_some_and(|d| d.abs() <= tol) => {}
            Ok(g) => bad.push(format!("{row}: at {r} mm geometry finds {}", g["flat_deviation"])),
            Err(e) => bad.push(e),
        }
    }
    bad
}

#[test]
fn round_cornered_rows_carry_geometrys_flat_deviation() {
    for line in [
        "setups --sides 2 --stock-diameter 20 --depth 1 --max-edges 12 --max-revolutions 12",
        "setups --sides 4 --stock-diameter 20000 --depth 1 --cutter-radius 10000",
        "setups --sides 6 --stock-diameter 20 --across-flats 17 --cutter-radius 50 --max-edges 3",
    ] {
        let bad = rows_unlike_geometry(line);
        assert!(bad.is_empty(), "{line}: {bad:#?}");
    }
}

#[test]
fn the_smallest_cutter_is_one_geometry_takes_with_flats_within_the_tolerance() {
    for (line, tol) in [
        ("setups --sides 4 --stock-diameter 20 --depth 1 --max-edges 4", 0.01),
        ("setups --sides 5 --stock-diameter 0.01 --depth 0.001 --max-edges 12 --max-revolutions 5", 0.01),
        ("setups --sides 8 --stock-diameter 50 --depth 2 --max-edges 12 --max-revolutions 3 --tolerance 1", 1.0),
        ("setups --sides 2 --stock-diameter 20 --depth 1 --max-edges 12 --max-revolutions 12", 0.01),
    ] {
        let bad = smallest_cutters_out_of_tolerance(line, tol);
        assert!(bad.is_empty(), "{line}: {bad:#?}");
    }
}

#[test]
fn the_table_prints_the_smallest_cutter_as_json_gives_it() {
    let line = "setups --sides 5 --stock-diameter 0.01 --depth 0.001 --max-edges 12 --max-revolutions 5";
    let rows: Vec<String> = json(line)["setups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["min_cutter_radius"].as_f64().map(|v| v.to_string()).unwrap_or_else(|| "-".into()))
        .collect();
    let text = run(line).unwrap();
    let table: Vec<String> = text
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|w| w.len() == 9 && w[0].starts_with(|c: char| c.is_ascii_digit()))
        .map(|w| w[8].to_string())
        .collect();
    assert_eq!(table, rows, "{text}");
}

/// For requests across the flags' ranges, every row's figures are
/// `geometry`'s, and every recommended cutter is one `geometry` takes
/// with flats within `--tolerance`.
#[test]
fn for_any_request_the_rows_and_the_smallest_cutters_agree_with_geometry() {
    use proptest::prelude::*;
    let cfg = ProptestConfig { cases: 16, ..ProptestConfig::default() };
    proptest!(cfg, |(sides in 2u32..=12, log_r2 in -2.0f64..3.0, through in prop::sample::select(vec![0.05, 0.2, 0.5, 0.9]),
                     max_edges in 1u32..=4, turns in 1u32..=3, log_tol in -3.0f64..0.0)| {
        let r2 = (10f64.powf(log_r2) * 1000.0).round() / 1000.0;
        let depth = (r2 * through * 1000.0).floor() / 1000.0;
        prop_assume!(depth >= 0.001 && depth < r2);
        let tol = (10f64.powf(log_tol) * 1e4).round() / 1e4;
        let line = format!("setups --sides {sides} --stock-radius {r2} --depth {depth} --max-edges {max_edges} --max-revolutions {turns} --tolerance {tol}");
        let unlike = rows_unlike_geometry(&line);
        prop_assert!(unlike.is_empty(), "{line}: {unlike:#?}");
        let out = smallest_cutters_out_of_tolerance(&line, tol);
        prop_assert!(out.is_empty(), "{line}: {out:#?}");
    });
}

/// The flat deviation changes sign as the cutter grows: convex with a
/// small cutter, concave with a larger one. The smallest cutter is in the
/// band where it crosses zero, however far below half the stock radius,
/// not where it creeps back within the tolerance at a cutter no lathe
/// swings.
#[test]
fn the_smallest_cutter_is_in_the_band_where_the_flats_cross_from_convex_to_concave() {
    let mut bad = Vec::new();
    for (line, ratio, edges, direction, band) in [
        ("setups --sides 8 --stock-diameter 50 --depth 2 --max-edges 12", "8/3", 3, "same", (12.6, 13.5)),
        ("setups --sides 6 --stock-diameter 20 --depth 1.5 --max-edges 12", "3", 2, "same", (2.84, 2.99)),
        ("setups --sides 4 --stock-diameter 20 --depth 1 --max-edges 12", "4", 1, "same", (1.22, 1.25)),
        // a band 0.01 mm wide: given to the figures it needs
        ("setups --sides 8 --stock-diameter 50 --depth 2 --max-edges 12", "4", 2, "same", (3.08, 3.09)),
    ] {
        let v = json(line);
        let row = v["setups"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["ratio"] == ratio && r["edges"] == edges && r["direction"] == direction)
            .unwrap_or_else(|| panic!("{line}: no {ratio} x {edges} {direction} row"));
        let r = row["min_cutter_radius"].as_f64();
        if !r.is_some_and(|r| band.0 <= r && r <= band.1) {
            bad.push(format!("{line}: {ratio} x {edges} {direction}: {r:?}, want {band:?}"));
            continue;
        }
        if row["warnings"].to_string().contains("smallest cutter") {
            bad.push(format!("{line}: {row}"));
        }
        let g = geometry(line, row, &r.unwrap().to_string()).unwrap();
        if !g["flat_deviation"].as_f64().is_some_and(|d| d.abs() <= 0.01) {
            bad.push(format!("{line}: at {r:?} geometry finds {}", g["flat_deviation"]));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}
