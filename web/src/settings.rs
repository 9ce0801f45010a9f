//! The settings form's check: the sync core's own console (`set`), on a
//! controller holding the board's settings as its `get` reply gave them,
//! so the page refuses exactly what the board refuses, in its words.

use polyturn_host::cli::figures;
use polyturn_host::cli::setup_plan::{changes, from_flags, summary, SetupArgs};
use polyturn_sync::console;
use polyturn_sync::{Config, Controller, Timing};

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
        setup: SetupArgs,
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
