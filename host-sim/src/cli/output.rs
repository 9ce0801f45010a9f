//! Files a command writes: all of them or none. Every output is rendered
//! first; then each is written to a temporary file beside its target and,
//! only when all were written, renamed into place. A refused command, a
//! missing directory or a full disk leaves every target as it was. Text
//! and binary files (a firmware .bin) alike.

use super::errors::{escaped, CliError, CliResult};
use std::path::{Path, PathBuf};

/// The files of one command, by the flag that named each.
#[derive(Default)]
pub struct Outputs {
    files: Vec<(&'static str, PathBuf, Vec<u8>)>,
}

impl Outputs {
    /// Adds `text` for the file given by `--flag`; a second flag naming
    /// the same file is refused (it would silently replace the first).
    pub fn add(&mut self, flag: &'static str, path: &Path, text: String) -> CliResult<()> {
        self.add_bytes(flag, path, text.into_bytes())
    }

    /// The same for a binary file.
    pub fn add_bytes(&mut self, flag: &'static str, path: &Path, bytes: Vec<u8>) -> CliResult<()> {
        // a directory (or `..`) cannot be replaced by a rename: refused
        // here, before any file is written
        if path.is_dir() || path.file_name().is_none() {
            return Err(CliError::flag(flag, format!("must name a file, not a directory (got '{}')", shown(path))));
        }
        if let Some((other, _, _)) = self.files.iter().find(|(_, p, _)| same_file(p, path)) {
            return Err(CliError::flag(flag, format!("names the same file as --{other} ('{}')", shown(path))));
        }
        self.files.push((flag, path.to_path_buf(), bytes));
        Ok(())
    }

    /// Writes every file, or none.
    #[cfg(not(target_family = "wasm"))]
    pub fn write(self) -> CliResult<Vec<PathBuf>> {
        let mut staged: Vec<(PathBuf, &PathBuf)> = Vec::new();
        for (flag, path, text) in &self.files {
            let tmp = temporary(path);
            if let Err(e) = std::fs::write(&tmp, text) {
                let _ = std::fs::remove_file(&tmp);
                unstage(&staged);
                return Err(CliError::flag(flag, format!("could not write '{}': {e}", shown(path))));
            }
            staged.push((tmp, path));
        }
        for (i, (tmp, path)) in staged.iter().enumerate() {
            if let Err(e) = std::fs::rename(tmp, path) {
                unstage(&staged[i..]);
                let flag = self.files[i].0;
                return Err(CliError::flag(flag, format!("could not write '{}': {e}", shown(path))));
            }
        }
        Ok(self.files.into_iter().map(|(_, p, _)| p).collect())
    }
}

/// In the browser there are no files: what a command would write is kept
/// for the page (`take_captured`), under the name the flag gave.
#[cfg(target_family = "wasm")]
impl Outputs {
    pub fn write(self) -> CliResult<Vec<PathBuf>> {
        let paths = self.files.iter().map(|(_, p, _)| p.clone()).collect();
        CAPTURED.with(|c| c.borrow_mut().extend(self.files.into_iter().map(|(_, p, b)| (shown(&p), b))));
        Ok(paths)
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

/// A path as one line of an error (control characters escaped).
fn shown(path: &Path) -> String {
    escaped(&path.display().to_string())
}

#[cfg(not(target_family = "wasm"))]
fn unstage(staged: &[(PathBuf, &PathBuf)]) {
    for (tmp, _) in staged {
        let _ = std::fs::remove_file(tmp);
    }
}

/// `dir/.name.polyturn-PID.tmp`: same directory, so the rename is atomic.
#[cfg(not(target_family = "wasm"))]
fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.polyturn-{}.tmp", std::process::id()))
}

/// The same file, however spelt (`f`, `./f`, `dir/../f`), existing or not.
fn same_file(a: &Path, b: &Path) -> bool {
    let key = |p: &Path| {
        let parent = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        parent.canonicalize().map(|d| d.join(p.file_name().unwrap_or_default())).unwrap_or_else(|_| p.to_path_buf())
    };
    a == b || key(a) == key(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("polyturn-out-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn one_unwritable_file_writes_none() {
        let d = dir("none");
        let mut o = Outputs::default();
        o.add("table", &d.join("t.json"), "{}".into()).unwrap();
        o.add("svg", Path::new("/nonexistent-dir/x.svg"), "<svg/>".into()).unwrap();
        let e = o.write().unwrap_err();
        assert!(e.0.starts_with("--svg could not write '/nonexistent-dir/x.svg'"), "{}", e.0);
        assert!(!d.join("t.json").exists());
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "no temporary left behind");
    }

    #[test]
    fn two_flags_naming_one_file_are_refused() {
        let d = dir("same");
        let mut o = Outputs::default();
        o.add("table", &d.join("f"), "a".into()).unwrap();
        assert!(o
            .add("svg", &d.join(".").join("f"), "b".into())
            .unwrap_err()
            .0
            .starts_with("--svg names the same file as --table"));
    }

    #[test]
    fn a_directory_is_refused_before_anything_is_written() {
        let d = dir("isdir");
        let mut o = Outputs::default();
        o.add("table", &d.join("t.json"), "{}".into()).unwrap();
        assert!(o.add("svg", &d, "<svg/>".into()).unwrap_err().0.starts_with("--svg must name a file"));
        assert!(o.add("svg", Path::new(".."), "<svg/>".into()).is_err());
        let e = Outputs { files: vec![("svg", PathBuf::from("/nonexistent-dir/a\nb"), Vec::new())] }.write();
        assert_eq!(e.unwrap_err().0.lines().count(), 1, "the path's newline is escaped");
    }

    #[test]
    fn all_files_are_written_when_all_can_be() {
        let d = dir("all");
        let mut o = Outputs::default();
        o.add("table", &d.join("t.json"), "{}".into()).unwrap();
        o.add("svg", &d.join("x.svg"), "<svg/>".into()).unwrap();
        o.write().unwrap();
        assert_eq!(std::fs::read_to_string(d.join("x.svg")).unwrap(), "<svg/>");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 2);
    }
}
