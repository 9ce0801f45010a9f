//! Files a command writes: all of them or none. Every output is rendered
//! first; then each regular file is written to a temporary file beside
//! its target, the devices, FIFOs and stdout (`-`) are written directly,
//! and only when all were written are the temporaries renamed into place.
//! A refused command, a missing directory or a full disk leaves every
//! regular file as it was. Text and binary files (a firmware .bin) alike.

mod target;

use super::errors::{escaped, CliError, CliResult};
use std::io::Write;
use std::path::{Path, PathBuf};
use target::{classify, identity, identity_of, Identity, Target};

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
}

impl Written {
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

    /// Writes every file, or (for regular files) none.
    #[cfg(not(target_family = "wasm"))]
    pub fn write(self) -> CliResult<Written> {
        let mut staged: Vec<(PathBuf, &Path)> = Vec::new();
        let fail = |o: &Output, staged: &[(PathBuf, &Path)], e: std::io::Error| {
            unstage(staged);
            CliError::flag(o.flag, format!("could not write '{}': {e}", shown(&o.given)))
        };
        for o in &self.files {
            if let Target::File(path) = &o.target {
                let tmp = temporary(path);
                if let Err(e) = std::fs::write(&tmp, &o.bytes).and_then(|()| keep_mode(path, &tmp)) {
                    let _ = std::fs::remove_file(&tmp);
                    return Err(fail(o, &staged, e));
                }
                staged.push((tmp, path));
            }
        }
        // a device or a pipe cannot be staged: written before any rename,
        // so that its failure (a full /dev/full) still leaves the files be
        for o in &self.files {
            if let Err(e) = stream(&o.target, &o.bytes) {
                return Err(fail(o, &staged, e));
            }
        }
        let regular = self.files.iter().filter(|o| matches!(o.target, Target::File(_)));
        for (i, ((tmp, path), o)) in staged.iter().zip(regular).enumerate() {
            if let Err(e) = std::fs::rename(tmp, path) {
                return Err(fail(o, &staged[i..], e));
            }
        }
        Ok(Written { to_stdout: self.files.iter().any(|o| o.target == Target::Stdout) })
    }
}

/// Writes a device, FIFO or stdout target; nothing for a regular file.
#[cfg(not(target_family = "wasm"))]
fn stream(target: &Target, bytes: &[u8]) -> std::io::Result<()> {
    match target {
        Target::File(_) => Ok(()),
        Target::Stdout => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)?;
            out.flush()
        }
        Target::Stream(path) => {
            let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
            f.write_all(bytes)?;
            f.flush()
        }
    }
}

/// In the browser there are no files: what a command would write is kept
/// for the page (`take_captured`), under the name the flag gave.
#[cfg(target_family = "wasm")]
impl Outputs {
    pub fn write(self) -> CliResult<Written> {
        CAPTURED.with(|c| c.borrow_mut().extend(self.files.into_iter().map(|o| (shown(&o.given), o.bytes))));
        Ok(Written { to_stdout: false })
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

#[cfg(not(target_family = "wasm"))]
fn unstage(staged: &[(PathBuf, &Path)]) {
    for (tmp, _) in staged {
        let _ = std::fs::remove_file(tmp);
    }
}

/// `dir/.name.polyturn-PID.tmp`: same directory, so the rename is atomic.
#[cfg(not(target_family = "wasm"))]
/// The file replaced keeps its permissions (a 0600 file stays private):
/// the rename brings the temporary's, so it gets the old file's first.
#[cfg(not(target_family = "wasm"))]
fn keep_mode(path: &Path, tmp: &Path) -> std::io::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) => std::fs::set_permissions(tmp, m.permissions()),
        Err(_) => Ok(()), // a new file: the umask's
    }
}

#[cfg(not(target_family = "wasm"))]
fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.polyturn-{}.tmp", std::process::id()))
}

#[cfg(test)]
mod tests;
