//! polyturn in the browser: the host library compiled to WebAssembly for
//! the page in `www/`. Nothing here computes geometry or speaks the
//! protocol itself: each export hands the page what the `polyturn` command
//! line or the real sync core gives, so the page and the CLI cannot differ.
//!
//! - `run`: any `polyturn` command line (geometry, setups, simulate, cam,
//!   compensate, sequence), its output and the files it would write;
//! - `check_setting`: the sync core's own `set` validation and message;
//! - `setting_fields`: each setting's unit, range and choices;
//! - `cam_lines`: a `polyturn cam --table` file as the console lines it sends;
//! - `flash_plan`: an image checked and planned for the ROM's DfuSe;
//! - `FakeBoard`, `FakeDfu`: the real console and a fake ROM bootloader,
//!   behind the byte streams WebSerial and WebUSB give, for the page's tests.

use wasm_bindgen::prelude::*;

mod board;
mod commands;
mod flash;
mod settings;

pub use board::FakeBoard;
pub use commands::run_args;
pub use flash::{plan_image, FakeDfu};
pub use settings::setting_error;

/// `polyturn <args>`: Ok is `{"out": text, "files": {name: text}}`, Err the
/// CLI's one-line error (without `error: `).
#[wasm_bindgen]
pub fn run(args: Vec<String>) -> Result<String, String> {
    run_args(&args)
}

/// The console's error for `set <name> <value>` on a board whose `get`
/// reply is `settings`, or undefined if the board would take it.
#[wasm_bindgen]
pub fn check_setting(settings: &str, name: &str, value: &str) -> Option<String> {
    setting_error(settings, name, value)
}

/// Each board setting's unit, range and choices, from the console's own
/// refusals (`settings::fields`), as JSON.
#[wasm_bindgen]
pub fn setting_fields() -> String {
    settings::fields()
}

/// The release image's file name without its extension, as `.ci/release-image`
/// names it (`polyturn-<version>-stm32f411ce`): the file the Flash view asks for.
#[wasm_bindgen]
pub fn release_image() -> String {
    format!("polyturn-{}-{}", polyturn_host::cli::VERSION, polyturn_host::flash::CHIP)
}

/// The guided setup's settings from the machinist's facts (the flags of
/// `polyturn device setup`) and the board's `get` reply.
#[wasm_bindgen]
pub fn guided_setup(args: Vec<String>, settings: &str) -> Result<String, String> {
    settings::guided(&args, settings)
}

/// The console lines that upload a `polyturn cam --table` (or
/// `compensate --table`) file, only to a board whose `get` reply
/// (`settings`) has the tool it was made for (`CamFile::fits`).
#[wasm_bindgen]
pub fn cam_lines(name: &str, text: &str, settings: &str) -> Result<Vec<String>, String> {
    let table = polyturn_host::cli::console_line::cam_table(name, text).map_err(|e| e.0)?;
    table.fits_settings(settings).map_err(|e| format!("upload-cam: {e}"))?;
    Ok(table.upload_lines(polyturn_host::cli::console_line::COMMAND_MAX))
}

/// The longest command line the board takes (tag excluded).
/// Whether a tagged line's text is a reply (`ok`, `ok ...`, `error: ...`)
/// and not, say, the port echoing the command (`console_line::is_reply`).
#[wasm_bindgen]
pub fn is_reply(line: &str) -> bool {
    polyturn_host::cli::console_line::is_reply(line)
}

/// The longest line the page takes from the board.
#[wasm_bindgen]
pub fn reply_max() -> usize {
    polyturn_host::cli::console_line::REPLY_MAX
}

#[wasm_bindgen]
pub fn command_max() -> usize {
    polyturn_host::cli::console_line::COMMAND_MAX
}
