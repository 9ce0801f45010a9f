//! Files a command writes: all of them or none. Every output is rendered
//! first; then each regular file is written to a temporary file beside
//! its target (`staged.rs`: a read-only file, or one we may not open for
//! writing, is refused here), the devices, FIFOs and stdout (`-`) are
//! written directly (`stream.rs`: a FIFO with no reader times out), and
//! only when all were written are the files put in place: a new one by
//! renaming its temporary, an existing one written through, as the
//! shell's `>` writes it (its owner, mode and hard links kept). A refused
//! command, a missing directory or a full disk leaves every regular file
//! as it was; Ctrl-C or SIGTERM meanwhile leaves no temporary
//! (`interrupt.rs`). Text and binary files (a firmware .bin) alike.

#[cfg(unix)]
mod interrupt;
#[cfg(not(target_family = "wasm"))]
mod staged;
#[cfg(not(target_family = "wasm"))]
mod stream;
mod target;

use super::errors::{escaped, CliError, CliResult};
use std::io::Write;
use std::path::{Path, PathBuf};
use target::{classify, identity, identity_of, Identity, Target};

/// How long a FIFO output may wait for a reader to open it, and a reader
/// may leave its bytes untaken, before the command gives up.
pub const FIFO_WAIT: std::time::Duration = std::time::Duration::from_secs(10);

/// One file to write: the flag and path that named it, where it goes.
struct Output {
    flag: &'static str,
    given: PathBuf,
    #[cfg_attr(target_family = "wasm", allow(dead_code))]
    target: Target,
    bytes: Vec<u8>,
}

/// The files of one command, by the flag that named each.
#[derive(Default)]
pub struct Outputs {
    files: Vec<Output>,
    /// the files the command reads, which no output may replace
    inputs: Vec<(String, Identity)>,
}

/// What was written; the command's report goes to stderr when its
/// stdout carries a file, so that `--svg - > x.svg` is a clean SVG.
#[derive(Debug)]
pub struct Written {
    to_stdout: bool,
    /// the files written that are not stdout, as given
    files: Vec<String>,
}

impl Written {
    /// "wrote A and B" for the files written (stdout aside), or nothing.
    pub fn wrote(&self) -> Option<String> {
        match self.files.as_slice() {
            [] => None,
            [one] => Some(format!("wrote {one}")),
            [rest @ .., last] => Some(format!("wrote {} and {last}", rest.join(", "))),
        }
    }

    /// The text for stdout: `report`, or nothing once it went to stderr.
    pub fn report(self, report: String) -> String {
        if !self.to_stdout {
            return report;
        }
        let _ = writeln!(std::io::stderr().lock(), "{report}");
        String::new()
    }
}

impl Outputs {
    /// Notes a file the command reads (`arg` names it in a refusal): an
    /// output naming it is refused, however spelt.
    pub fn reading(&mut self, arg: &str, path: &Path) {
        self.inputs.push((arg.to_string(), identity_of(path)));
    }

    /// Adds `text` for the file given by `--flag`; a second flag naming
    /// the same file is refused (it would silently replace the first).
    pub fn add(&mut self, flag: &'static str, path: &Path, text: String) -> CliResult<()> {
        self.add_bytes(flag, path, text.into_bytes())
    }

    /// The same for a binary file.
    pub fn add_bytes(&mut self, flag: &'static str, path: &Path, bytes: Vec<u8>) -> CliResult<()> {
        // refused here, before any file is written
        let target = classify(path).map_err(|why| CliError::flag(flag, format!("{why} (got '{}')", shown(path))))?;
        let id = identity(&target);
        if let Some((arg, _)) = self.inputs.iter().find(|(_, i)| *i == id) {
            return Err(CliError::flag(flag, format!("must not be the {arg} it reads (got '{}')", shown(path))));
        }
        if let Some(other) = self.files.iter().find(|o| identity(&o.target) == id) {
            return Err(CliError::flag(flag, format!("names the same file as --{} ('{}')", other.flag, shown(path))));
        }
        self.files.push(Output { flag, given: path.to_path_buf(), target, bytes });
        Ok(())
    }

    /// Writes every file, or (for regular files) none; a FIFO waits at most
    /// [`FIFO_WAIT`] for its reader.
    #[cfg(not(target_family = "wasm"))]
    pub fn write(self) -> CliResult<Written> {
        self.write_within(FIFO_WAIT)
    }

    /// The same, a FIFO waiting at most `wait` for its reader (and for room).
    #[cfg(not(target_family = "wasm"))]
    pub fn write_within(self, wait: std::time::Duration) -> CliResult<Written> {
        #[cfg(unix)]
        let mut guard = interrupt::Guard::new();
        let mut staged: Vec<staged::Staged> = Vec::new();
        let fail = |o: &Output, staged: &[staged::Staged], why: String| {
            staged::unstage(staged);
            CliError::flag(o.flag, why)
        };
        let could_not = |o: &Output, e: std::io::Error| match o.target {
            Target::Stdout => format!("could not write to stdout: {e}"),
            _ => format!("could not write '{}': {e}", shown(&o.given)),
        };
        for o in &self.files {
            if let Target::File(path) = &o.target {
                #[cfg(unix)]
                guard.add(&staged::temporary(path));
                match staged::stage(path, &o.bytes) {
                    Ok(s) => staged.push(s),
                    Err(why) => return Err(fail(o, &staged, why.shown(&shown(&o.given)))),
                }
            }
        }
        // a device or a pipe cannot be staged: written before any file is
        // put in place, so that its failure (a full /dev/full, a FIFO no one
        // reads) still leaves the files be
        for o in &self.files {
            if let Err(e) = unstaged(&o.target, &o.bytes, wait) {
                return Err(fail(o, &staged, could_not(o, e)));
            }
        }
        let regular = self.files.iter().filter(|o| matches!(o.target, Target::File(_)));
        for (i, (s, o)) in staged.iter().zip(regular).enumerate() {
            if let Err(e) = s.commit(&o.bytes) {
                return Err(fail(o, &staged[i..], could_not(o, e)));
            }
        }
        let files = self.files.iter().filter(|o| o.target != Target::Stdout).map(|o| shown(&o.given)).collect();
        Ok(Written { to_stdout: self.files.iter().any(|o| o.target == Target::Stdout), files })
    }
}

/// Writes a device, FIFO or stdout target; nothing for a regular file.
#[cfg(not(target_family = "wasm"))]
fn unstaged(target: &Target, bytes: &[u8], wait: std::time::Duration) -> std::io::Result<()> {
    match target {
        Target::File(_) => Ok(()),
        Target::Stdout => {
            let mut out = std::io::stdout().lock();
            // a reader that closed the pipe (`| head`) took what it wanted:
            // no error, as for the report
            match out.write_all(bytes).and_then(|()| out.flush()) {
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                r => r,
            }
        }
        Target::Stream(path) => stream::write(path, bytes, wait),
    }
}

/// In the browser there are no files: what a command would write is kept
/// for the page (`take_captured`), under the name the flag gave.
#[cfg(target_family = "wasm")]
impl Outputs {
    pub fn write(self) -> CliResult<Written> {
        let files = self.files.iter().map(|o| shown(&o.given)).collect();
        CAPTURED.with(|c| c.borrow_mut().extend(self.files.into_iter().map(|o| (shown(&o.given), o.bytes))));
        Ok(Written { to_stdout: false, files })
    }
}

#[cfg(target_family = "wasm")]
thread_local! {
    static CAPTURED: std::cell::RefCell<Vec<(String, Vec<u8>)>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The files the last commands would have written, by name (the browser's).
#[cfg(target_family = "wasm")]
pub fn take_captured() -> Vec<(String, Vec<u8>)> {
    CAPTURED.with(|c| std::mem::take(&mut *c.borrow_mut()))
}

/// An output as a report names it: `-` is "stdout".
pub fn named(path: &Path) -> String {
    if path.as_os_str() == "-" {
        "stdout".into()
    } else {
        shown(path)
    }
}

/// A path as one line of an error (control characters escaped).
fn shown(path: &Path) -> String {
    escaped(&path.display().to_string())
}

#[cfg(test)]
mod tests;
