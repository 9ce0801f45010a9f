//! A regular file's output, staged before anything is put in place: its
//! bytes written to `.NAME.polyturn-PID.tmp` beside it (so that a full disk
//! or a missing directory is found while every file is as it was) and, for
//! a file that exists, the file opened for writing now, so that one we may
//! not write is refused before anything changes.
//!
//! Put in place, a new file is the temporary renamed (atomic: never half
//! there). An existing one is written through, as the shell's `>` writes
//! it: the same inode, so its owner and mode stay and every hard link sees
//! the new text (a rename would leave a root-owned copy, and the other
//! links with the old text); its temporary is removed first, so its room
//! on the disk is the new text's.
//!
//! A read-only file (no write permission for anyone: `chmod 444`) is
//! refused, as the shell's `>` refuses it, and even for root, whom the
//! shell would let write: a file made read-only is one to keep.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// One regular file, staged.
pub struct Staged {
    tmp: PathBuf,
    path: PathBuf,
    /// the existing file, open for writing (not truncated yet)
    through: Option<File>,
}

/// Why a file could not be staged.
pub enum Refused {
    ReadOnly(u32),
    Io(std::io::Error),
}

impl Refused {
    /// The refusal, for `path` as the user gave it.
    pub fn shown(&self, path: &str) -> String {
        match self {
            Refused::ReadOnly(mode) => format!(
                "must name a file it may write (got '{path}': read-only, mode {mode:04o}; chmod u+w it, or name another)"
            ),
            Refused::Io(e) => format!("could not write '{path}': {e}"),
        }
    }
}

pub fn stage(path: &Path, bytes: &[u8]) -> Result<Staged, Refused> {
    let through = match std::fs::metadata(path) {
        Ok(m) if m.permissions().readonly() => return Err(Refused::ReadOnly(mode(&m))),
        Ok(_) => Some(std::fs::OpenOptions::new().write(true).open(path).map_err(Refused::Io)?),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(Refused::Io(e)),
    };
    let tmp = temporary(path);
    if let Err(e) = std::fs::write(&tmp, bytes) {
        let _ = std::fs::remove_file(&tmp);
        return Err(Refused::Io(e));
    }
    Ok(Staged { tmp, path: path.to_path_buf(), through })
}

impl Staged {
    /// Puts the file in place: renamed if new, written through if not.
    pub fn commit(&self, bytes: &[u8]) -> std::io::Result<()> {
        match &self.through {
            None => std::fs::rename(&self.tmp, &self.path),
            Some(f) => {
                std::fs::remove_file(&self.tmp)?;
                let mut f = f;
                f.set_len(0)?;
                f.write_all(bytes)?;
                f.flush()
            }
        }
    }
}

/// Removes the temporaries (those not put in place yet).
pub fn unstage(staged: &[Staged]) {
    for s in staged {
        let _ = std::fs::remove_file(&s.tmp);
    }
}

/// `dir/.name.polyturn-PID.tmp`: same directory, so the rename is atomic.
pub fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.polyturn-{}.tmp", std::process::id()))
}

#[cfg(unix)]
fn mode(m: &std::fs::Metadata) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    m.permissions().mode() & 0o7777
}

#[cfg(not(unix))]
fn mode(_: &std::fs::Metadata) -> u32 {
    0o444
}
