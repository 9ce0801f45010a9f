//! `setups` says what it assumed, what to run next and what to beware of
//!, and still exits 0 with its table.

use crate::cli::dispatch;
use serde_json::Value;

pub(super) fn run(line: &str) -> Result<String, String> {
    dispatch(&line.split_whitespace().map(String::from).collect::<Vec<_>>()).map_err(|e| e.0)
}

pub(super) fn json(line: &str) -> Value {
    serde_json::from_str(&run(&format!("{line} --json")).unwrap()).unwrap()
}

const HEX: &str = "setups --sides 6 --stock-radius 10 --across-flats 17 --max-edges 3";

#[test]
fn the_first_rows_geometry_line_reproduces_its_figures() {
    let v = json(&format!("{HEX} --cutter-radius 50 --rpm 300"));
    let line = v["geometry_command"].as_str().unwrap();
    assert_eq!(
        line,
        "polyturn geometry --cutter-radius 50 --stock-radius 10 --across-flats 17 --ratio 2 --edges 3 --direction same"
    );
    let g: Value = serde_json::from_str(&run(&format!("{} --json", &line["polyturn ".len()..])).unwrap()).unwrap();
    let row = &v["setups"][0];
    for field in ["ratio", "edges", "direction", "revolutions", "corners_sharp"] {
        assert_eq!(g[field], row[field], "{field}");
    }
    let (planned, drawn) = (row["flat_deviation"].as_f64().unwrap(), g["flat_deviation"].as_f64().unwrap());
    assert!((planned - drawn).abs() < 2e-4, "{planned} against {drawn}");
    let human = run(&format!("{HEX} --cutter-radius 50 --rpm 300")).unwrap();
    assert!(human.contains(&format!("\n  {line}\n  polyturn simulate ")), "{human}");
}

#[test]
fn the_simulate_line_runs_as_printed_at_the_given_or_an_example_speed() {
    let given = json("setups --sides 6 --stock-diameter 20 --depth 1.5 --rpm 120").to_string();
    assert!(given.contains("--rpm 120 --revolutions 10"), "{given}");
    let v = json(&format!("{HEX} --cutter-radius 50"));
    let line = v["simulate_command"].as_str().unwrap();
    assert!(line.ends_with("--direction same --rpm 300 --revolutions 10"), "{line}");
    let out = run(&line["polyturn ".len()..]).unwrap();
    assert!(out.contains("cut: 6 sides"), "{out}");
    assert_eq!(v["warnings"], Value::Array(vec![]), "a line that runs is not warned of");
}

#[test]
fn a_simulate_line_the_cli_would_refuse_is_said_so_with_the_reason() {
    let text = run("setups --sides 6 --stock-radius 10 --depth 1.5 --cutter-radius 50 --rpm 6500").unwrap();
    let refused = text.lines().find(|l| l.starts_with("warning: the simulate line is refused as printed: --rpm "));
    assert!(refused.is_some(), "{text}");
}

#[test]
fn an_assumed_cutter_is_said_with_why_and_a_given_one_is_not_called_assumed() {
    let assumed = run("setups --sides 6 --stock-radius 10 --depth 1.5").unwrap();
    assert!(assumed.contains("\ncutter radius 50 mm assumed: 5 x the stock radius"), "{assumed}");
    let v = json("setups --sides 6 --stock-radius 10 --depth 1.5");
    assert!(v["cutter_radius_assumed"].as_str().unwrap().contains("give --cutter-radius"), "{v}");
    let given = run("setups --sides 6 --stock-radius 10 --depth 1.5 --cutter-radius 60").unwrap();
    assert!(given.contains("\ncutter radius 60 mm (--cutter-radius)\n") && !given.contains("mm assumed"), "{given}");
    assert!(
        json("setups --sides 6 --stock-radius 10 --depth 1.5 --cutter-radius 60")["cutter_radius_assumed"].is_null()
    );
}

#[test]
fn an_assumed_cutter_is_printed_as_a_machinist_would_type_it() {
    // 5 x 0.23 and 5 x 0.00105 are not exact in binary
    for (stock, want) in [("0.46", "1.15"), ("0.14", "0.35"), ("0.0021", "0.00525")] {
        let out = run(&format!("setups --sides 6 --stock-diameter {stock} --depth 0.001 --max-edges 3")).unwrap();
        assert!(out.contains(&format!("\ncutter radius {want} mm assumed")), "{out}");
        assert!(out.contains(&format!("--cutter-radius {want} ")), "{out}");
    }
}

#[test]
fn every_dash_in_the_table_is_explained_by_a_note() {
    for line in [
        "setups --sides 6 --stock-radius 20 --depth 3 --rpm 300",
        "setups --sides 6 --stock-radius 10 --depth 1.5 --cutter-radius 50",
        "setups --sides 6 --stock-radius 10 --depth 1.5",
    ] {
        let text = run(line).unwrap();
        let table: Vec<&str> = text.lines().filter(|l| l.starts_with(|c: char| c.is_ascii_digit())).collect();
        let dash = |col: usize| table.iter().any(|r| r.split_whitespace().nth(col) == Some("-"));
        if dash(6) || dash(7) {
            assert!(text.contains("\"-\" in cutter rpm and tip m/s: no --rpm"), "{line}\n{text}");
        }
        assert_eq!(dash(8), text.contains("\"-\" in min R1 mm: "), "{line}\n{text}");
    }
    let text = run("setups --sides 6 --stock-radius 20 --depth 3 --rpm 300").unwrap();
    assert!(text.contains(
        "no cutter radius up to 2000 mm keeps the flats within --tolerance 0.01 mm in a section geometry takes"
    ));
    let given = run("setups --sides 6 --stock-radius 10 --depth 1.5 --cutter-radius 50").unwrap();
    assert!(given.contains("worked out only when the cutter radius is assumed (no --cutter-radius)"), "{given}");
}

#[test]
fn setups_geometry_would_refuse_as_round_are_left_out_and_counted() {
    // a 3 mm cutter 0.1 mm deep: the flattest rows were round sections
    // that geometry refuses (the first row's line was refused as printed)
    let line = "setups --sides 20 --stock-radius 10 --depth 0.1 --cutter-radius 3 --max-edges 12";
    let v = json(line);
    let notes = v["notes"].to_string();
    assert!(notes.contains("11 more left out: with this cutter their section is nearly round"), "{notes}");
    let geometry = v["geometry_command"].as_str().unwrap();
    assert!(run(&geometry["polyturn ".len()..]).is_ok(), "{geometry}");
    assert_eq!(v["warnings"].as_array().map(Vec::len), Some(0), "{v}");
}

/// Every row `setups` prints (the whole table, not only the first row's
/// line) with the cutter it was worked out for: `geometry`'s line for it,
/// checked as `geometry` checks it; None where geometry takes it.
fn rows_geometry_refuses(line: &str) -> Vec<String> {
    let v = json(line);
    let given = line.split_whitespace().collect::<Vec<_>>();
    let flag = |name: &str| given.iter().position(|w| *w == name).map(|i| format!("{name} {}", given[i + 1]));
    let stock = flag("--stock-radius").or(flag("--stock-diameter")).unwrap();
    let cut = flag("--depth").or(flag("--across-flats")).unwrap();
    let r1 = v["cutter_radius"].as_f64().unwrap();
    let rows = v["setups"].as_array().unwrap();
    rows.iter()
        .filter_map(|row| {
            let g = format!(
                "geometry --cutter-radius {r1} {stock} {cut} --ratio {} --edges {} --direction {}",
                row["ratio"].as_str().unwrap(),
                row["edges"],
                row["direction"].as_str().unwrap()
            );
            run(&g).err().map(|e| format!("{g}: {e}"))
        })
        .collect()
}

#[test]
fn a_degenerate_section_is_left_out_and_a_cutter_past_the_longest_length_is_not_assumed() {
    // a cut 0.998 of the stock radius deep: the section is 2 µm across,
    // judged on the same exact bins by both (a polyline through the pass
    // once called it round in `geometry` and a polygon in `setups`)
    let deep = "setups --sides 20 --stock-radius 0.5 --depth 0.499 --max-edges 6";
    assert_eq!(rows_geometry_refuses(deep), Vec::<String>::new());
    // 2 500 mm stock: the assumed cutter, 5 x, is past --cutter-radius's 10 000 mm
    let big = "setups --sides 6 --stock-radius 2500 --depth 100";
    let e = run(big).unwrap_err();
    assert!(e.starts_with("--cutter-radius must be given for a stock radius over 2000 mm"), "{e}");
    // given, it is the machinist's own cutter, and the rows come back
    assert!(json(&format!("{big} --cutter-radius 9000"))["setups"].as_array().is_some_and(|r| !r.is_empty()));
}

/// For any request in the flags' ranges, from a fine cut to one all but
/// through the bar and from a pin to a 20 m bar, every row printed is one
/// `geometry` takes as printed.
#[test]
fn every_row_setups_prints_is_one_geometry_takes() {
    use proptest::prelude::*;
    let cfg = ProptestConfig { cases: 24, ..ProptestConfig::default() };
    proptest!(cfg, |(sides in 2u32..=24, log_r2 in -2.0f64..4.0, through in prop::sample::select(vec![0.05, 0.5, 0.9, 0.99, 0.998, 0.9995]),
                     max_edges in 1u32..=6, turns in 1u32..=3, cutter in prop::option::of(1.02f64..20.0), diameter in any::<bool>())| {
        let r2 = (10f64.powf(log_r2) * 1000.0).round() / 1000.0;
        let depth = (r2 * through * 1000.0).floor() / 1000.0;
        prop_assume!(depth >= 0.001 && depth < r2);
        let stock = if diameter { format!("--stock-diameter {}", 2.0 * r2) } else { format!("--stock-radius {r2}") };
        let mut line = format!("setups --sides {sides} {stock} --depth {depth} --max-edges {max_edges} --max-revolutions {turns}");
        if let Some(k) = cutter {
            line += &format!(" --cutter-radius {}", ((depth * k * 1000.0).ceil() / 1000.0).min(10_000.0));
        }
        if cutter.is_none() && crate::planner::default_cutter(r2) > 10_000.0 {
            // no cutter to assume: refused, naming the flag that gives one
            let e = run(&line).unwrap_err();
            prop_assert!(e.starts_with("--cutter-radius must be given"), "{line}: {e}");
            return Ok(());
        }
        let refused = rows_geometry_refuses(&line);
        prop_assert!(refused.is_empty(), "{line}: {refused:#?}");
    });
}

#[test]
fn stock_whose_assumed_cutter_geometry_refuses_is_refused_naming_cutter_radius() {
    // 5 x 2000.5 mm is 10002.5 mm, past geometry's 10000 mm
    let e = run("setups --sides 6 --stock-diameter 4001 --depth 1 --max-edges 3").unwrap_err();
    assert!(e.starts_with("--cutter-radius must be given "), "{e}");
    assert!(e.contains("10002.5 mm") && e.contains("0.001..=10000 mm"), "{e}");
    assert!(!e.contains("no setup cuts"), "{e}");
    // at 4000 mm the assumed 10000 mm is taken, and a cutter given is used
    assert!(run("setups --sides 6 --stock-diameter 4000 --depth 1 --max-edges 3").is_ok());
    let given = run("setups --sides 6 --stock-diameter 4001 --depth 1 --max-edges 3 --cutter-radius 10000").unwrap();
    assert!(!given.contains("no setup cuts"), "{given}");
}
