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
        "no cutter radius up to 2000 mm (100 x the stock radius) keeps the flats within --tolerance 0.01 mm"
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
