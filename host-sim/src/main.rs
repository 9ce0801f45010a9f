//! `polyturn`: the host command-line tool.
use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    match polyturn_host::cli::dispatch(&argv) {
        Ok(text) => {
            // A closed pipe (`polyturn ... | head`) is not an error worth a panic.
            if !text.is_empty() {
                let _ = writeln!(std::io::stdout().lock(), "{text}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            let _ = writeln!(std::io::stderr().lock(), "error: {}", e.0);
            ExitCode::from(2)
        }
    }
}
