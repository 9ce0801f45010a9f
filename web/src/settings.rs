//! The settings form's check: the sync core's own console (`set`), on a
//! controller holding the board's settings as its `get` reply gave them,
//! so the page refuses exactly what the board refuses, in its words.

use polyturn_host::cli::figures;
use polyturn_host::cli::guided::{changes, from_flags, summary, GuidedArgs};
use polyturn_sync::config::NAMES;
use polyturn_sync::console;
use polyturn_sync::{Config, Controller, Timing};
use serde_json::{json, Value};

/// Each setting's unit on the page, as the console's words and the book
/// give it (docs/src/console.md); a setting with fixed choices has none.
const UNITS: &[(&str, &str)] = &[
    ("cpr", "counts/rev"),
    ("steps", "steps/rev"),
    ("ratio", "cutter turns/lathe turn"),
    ("edges", "edges"),
    ("max-rate", "steps/s"),
    ("max-accel", "steps/s²"),
    ("ferror", "steps"),
    ("phase", "° of the cutter"),
    ("dir-setup", "ns"),
    ("pulse", "ns"),
    ("max-rpm", "rpm"),
    ("cutter-cpr", "counts/rev"),
    ("lost-steps", "steps"),
    ("start-rate", "steps/s"),
    ("pwm-hz", "Hz"),
    ("bldc-tau", "ms"),
];

/// What the page needs to draw each setting's field, asked of the console
/// itself so it cannot drift from the firmware: `[{name, unit, min, max,
/// choices, allowed}]`, where `allowed` is the console's own words when
/// refusing a bad value, `min..=max` the range in them, and `choices` the
/// words in them that `set` takes (a `<select>`), empty for a number.
pub fn fields() -> String {
    let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    let defaults = console::handle(b"get", &mut ctl).0.to_string();
    let rows: Vec<Value> = NAMES
        .iter()
        .map(|&name| {
            let refusal = console::handle(format!("set {name} ?").as_bytes(), &mut ctl).0.to_string();
            let allowed = refusal.strip_prefix(&format!("error: {name} ")).unwrap_or(&refusal).to_string();
            let (min, max) = range_in(&allowed).unzip();
            let unit = UNITS.iter().find(|(n, _)| *n == name).map(|(_, u)| *u);
            json!({"name": name, "unit": unit, "min": min, "max": max,
                   "choices": choices_in(&allowed, &defaults, name), "allowed": allowed})
        })
        .collect();
    Value::Array(rows).to_string()
}

/// `a..=b` in the console's words ("4..=1000000 counts per lathe rev").
fn range_in(allowed: &str) -> Option<(i64, i64)> {
    let word = allowed.split_whitespace().find(|w| w.contains("..="))?;
    let (a, b) = word.split_once("..=")?;
    Some((a.parse().ok()?, b.parse().ok()?))
}

/// The words of "same or opposite", "stepper, bldc or none" or "high or
/// low (the active level)", if `set` takes every one: the choices.
fn choices_in(allowed: &str, settings: &str, name: &str) -> Vec<String> {
    let list = allowed.split(" (").next().unwrap_or("");
    let words: Vec<String> = list.split([',', ' ']).filter(|w| !w.is_empty() && *w != "or").map(String::from).collect();
    let all_taken = words.len() >= 2 && words.iter().all(|w| setting_error(settings, name, w).is_none());
    if all_taken {
        words
    } else {
        Vec::new()
    }
}

/// The board's `set` error for this value, or None if it would be taken.
pub fn setting_error(settings: &str, name: &str, value: &str) -> Option<String> {
    let mut ctl = Controller::new(board_config(settings), Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    let line = format!("set {name} {value}");
    let (reply, _) = console::handle(line.as_bytes(), &mut ctl);
    reply.starts_with("error").then(|| reply.to_string())
}

/// The settings of a `get` reply (`ok cpr=2400 steps=3200 ...`), read as
/// `polyturn device setup` reads them; the defaults if it is not one.
fn board_config(settings: &str) -> Config {
    figures::parse_settings(settings).unwrap_or_default()
}

/// The guided setup: the facts as `polyturn device setup
/// --non-interactive` takes them (`args`), against the board's `get`
/// reply; `{"order": [[name, value], ...], "summary": text}`, the
/// settings in an order the board accepts and what they mean.
pub fn guided(args: &[String], settings: &str) -> Result<String, String> {
    use clap::Parser;
    #[derive(Parser)]
    #[command(name = "setup", no_binary_name = true)]
    struct Flags {
        #[command(flatten)]
        setup: GuidedArgs,
    }
    let flags = Flags::try_parse_from(args.iter().chain(["--non-interactive".to_string()].iter()))
        .map_err(|e| e.to_string().lines().next().unwrap_or("").trim_start_matches("error: ").to_string())?;
    let facts = from_flags(&flags.setup).map_err(|e| e.0)?;
    let current = figures::parse_settings(settings).ok_or("the board's settings could not be read (get)")?;
    let (order, now) = figures::send_order(&current, &changes(&facts))?;
    Ok(serde_json::json!({"order": order, "summary": summary(&now, &order)}).to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_setting_has_a_unit_or_the_consoles_choices() {
        let f: Vec<Value> = serde_json::from_str(&fields()).unwrap();
        assert_eq!(f.len(), NAMES.len());
        let by = |n: &str| f.iter().find(|r| r["name"] == n).unwrap().clone();
        for r in &f {
            let choices = r["choices"].as_array().unwrap();
            assert!(r["unit"].is_string() == choices.is_empty(), "a unit or choices, not both: {r}");
        }
        assert_eq!(by("dir")["choices"], json!(["same", "opposite"]));
        assert_eq!(by("drive")["choices"], json!(["stepper", "bldc", "none"]));
        assert_eq!(by("enable")["choices"], json!(["high", "low"]));
        assert_eq!(by("bldc-out")["choices"], json!(["esc50", "esc400", "oneshot125", "pwm"]));
        assert_eq!((by("cpr")["min"].clone(), by("cpr")["max"].clone()), (json!(4), json!(1_000_000)));
        assert_eq!((by("phase")["min"].clone(), by("phase")["unit"].clone()), (json!(-360), json!("° of the cutter")));
        assert_eq!(by("ratio")["choices"], json!([]), "free text: 5/2, 11:3, 2.5");
    }

    fn board_get(ctl: &mut Controller) -> String {
        console::handle(b"get", ctl).0.to_string()
    }

    #[test]
    fn the_form_refuses_what_the_console_refuses_in_its_words() {
        let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        ctl.start(0, 0, 0);
        let settings = board_get(&mut ctl);
        for (name, value) in
            [("cpr", "0"), ("ratio", "1/0"), ("ratio", "1:0"), ("max-rate", "abc"), ("nonsense", "1"), ("edges", "13")]
        {
            let line = format!("set {name} {value}");
            let board = console::handle(line.as_bytes(), &mut ctl).0.to_string();
            assert!(board.starts_with("error"), "{board}");
            assert_eq!(setting_error(&settings, name, value), Some(board), "{line}");
        }
        assert_eq!(setting_error(&settings, "ratio", "5/2"), None);
        // the shop's notation, as the console takes it
        assert_eq!(setting_error(&settings, "ratio", "5:2"), None);
        assert_eq!(setting_error(&settings, "ratio", "2:1"), None);
    }

    #[test]
    fn the_check_uses_the_boards_settings_not_the_defaults() {
        let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        ctl.start(0, 0, 0);
        assert!(console::handle(b"set cpr 1000", &mut ctl).0.starts_with("ok"));
        assert!(console::handle(b"set ratio 7/3", &mut ctl).0.starts_with("ok"));
        let settings = board_get(&mut ctl);
        assert_eq!(board_get(&mut Controller::new(board_config(&settings), Timing::FIRMWARE)), settings);
    }

    #[test]
    fn the_guided_setup_derives_the_settings_the_cli_sends() {
        let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        ctl.start(0, 0, 0);
        let args: Vec<String> =
            "--encoder-lines 500 --motor-steps 200 --microsteps 8 --reduction 2 --max-lathe-rpm 900"
                .split_whitespace()
                .map(String::from)
                .collect();
        let r: serde_json::Value = serde_json::from_str(&guided(&args, &board_get(&mut ctl)).unwrap()).unwrap();
        let order: Vec<(String, String)> = serde_json::from_value(r["order"].clone()).unwrap();
        assert!(order.contains(&("cpr".into(), "2000".into())), "4 x 500 lines: {order:?}");
        assert!(order.contains(&("steps".into(), "3200".into())), "200 x 8 x 2: {order:?}");
        assert!(order.contains(&("max-rpm".into(), "900".into())), "{order:?}");
        for (n, v) in &order {
            let line = format!("set {n} {v}");
            assert!(console::handle(line.as_bytes(), &mut ctl).0.starts_with("ok"), "{line}");
        }
        let e = guided(&["--encoder-lines".into(), "0".into()], &board_get(&mut ctl)).unwrap_err();
        assert!(e.contains("--encoder-lines"), "{e}");
    }
}
