//! The command line in the browser: the same `dispatch` as the `polyturn`
//! binary. Where the CLI writes files (`--svg`, `--table`), the browser
//! gets their text back (`cli::output` keeps them on wasm).

use serde_json::{json, Value};

/// `polyturn <args>` as `{"out": ..., "files": {...}}`, or the error line.
pub fn run_args(args: &[String]) -> Result<String, String> {
    let ran = polyturn_host::cli::dispatch(args);
    // taken whatever the outcome: a run that fails after writing its files
    // (a simulation whose controller latched a fault) must not leave them
    // to be handed out with the next command's
    let files = captured();
    Ok(json!({"out": ran.map_err(|e| e.0)?, "files": files}).to_string())
}

#[cfg(target_family = "wasm")]
fn captured() -> Value {
    let files = polyturn_host::cli::output::take_captured();
    Value::Object(files.into_iter().map(|(n, b)| (n, Value::String(String::from_utf8_lossy(&b).into()))).collect())
}

/// On the host (tests) the files are written as the CLI writes them.
#[cfg(not(target_family = "wasm"))]
fn captured() -> Value {
    Value::Object(serde_json::Map::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(line: &str) -> Vec<String> {
        line.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn a_command_gives_what_the_cli_prints() {
        let line =
            "geometry --cutter-radius 40 --stock-radius 20 --depth 3 --ratio 2 --edges 3 --direction same --json";
        let r: Value = serde_json::from_str(&run_args(&args(line)).unwrap()).unwrap();
        let cli = polyturn_host::cli::dispatch(&args(line)).unwrap();
        assert_eq!(r["out"], Value::String(cli));
        assert_eq!(serde_json::from_str::<Value>(r["out"].as_str().unwrap()).unwrap()["sides"], 6);
    }

    #[test]
    fn a_bad_flag_gives_the_cli_error_naming_it() {
        let e = run_args(&args(
            "geometry --cutter-radius -4 --stock-radius 20 --depth 3 --ratio 2 --edges 3 --direction same",
        ))
        .unwrap_err();
        assert!(e.starts_with("--cutter-radius"), "{e}");
    }
}
