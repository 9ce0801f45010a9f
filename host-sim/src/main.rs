//! `polyturn`: the host command-line tool.
use std::io::{ErrorKind, Write};
use std::process::ExitCode;

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    match polyturn_host::cli::dispatch_reported(&argv) {
        Ok(text) => match print(&text) {
            Ok(()) => ExitCode::SUCCESS,
            // the reader took what it wanted (`polyturn ... | head`)
            Err(e) if e.kind() == ErrorKind::BrokenPipe => ExitCode::SUCCESS,
            // a full disk or a closed stdout: the report is not where the
            // caller asked for it, which is no success
            Err(e) => fail(&format!("the report could not be written to standard output: {e}")),
        },
        // the run's report, then why it failed: the failure is the exit
        // status and stderr's line whatever became of the report
        Err(polyturn_host::cli::Failed { report: Some(text), error }) => {
            let _ = print(&text);
            fail(&error.0)
        }
        Err(f) => fail(&f.error.0),
    }
}

/// The report, flushed: a write that fails only at the flush (a full
/// disk behind a redirect) fails here, not silently at exit.
fn print(text: &str) -> std::io::Result<()> {
    if text.is_empty() {
        return Ok(());
    }
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}")?;
    out.flush()
}

/// Exit status 2 for an error, 130 (the shell's for SIGINT) for a command
/// the machinist cancelled with Ctrl-C.
fn fail(why: &str) -> ExitCode {
    let _ = writeln!(std::io::stderr().lock(), "error: {why}");
    match polyturn_host::cli::device::prompt::cancelled_by_ctrl_c() {
        true => ExitCode::from(130),
        false => ExitCode::from(2),
    }
}
