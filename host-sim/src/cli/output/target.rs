//! What an output path names, and which file it is. A rename replaces
//! whatever the path holds, so only a regular file (or a path not made
//! yet) may be replaced, and then at the end of its symlinks: the link
//! stays a link and the file it names is the one written. A device or a
//! FIFO is written where it is (renaming over /dev/full would turn the
//! device into a plain file).

use std::path::{Path, PathBuf};

/// Where one output goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A regular file, existing or not, every symlink followed: staged
    /// beside it and renamed over it.
    File(PathBuf),
    /// A character device or a FIFO: opened and written in place.
    Stream(PathBuf),
    /// `-`: standard output.
    Stdout,
}

/// Which file a path is, however spelt (`f`, `./f`, a symlink, a hard
/// link): the inode when it exists, else the absolute path it will have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Identity {
    #[cfg_attr(not(unix), allow(dead_code))]
    Node(u64, u64),
    Path(PathBuf),
    Stdout,
}

/// Linux gives up after 40 links (ELOOP); so do we, rather than loop.
const MAX_LINKS: usize = 40;

/// Where `path` writes, or why it cannot be written to.
pub fn classify(path: &Path) -> Result<Target, String> {
    if path.as_os_str() == "-" {
        return Ok(Target::Stdout);
    }
    #[cfg(windows)]
    if is_windows_device(path) {
        return Ok(Target::Stream(path.to_path_buf()));
    }
    let dir = || "must name a file, not a directory".to_string();
    // the kernel follows every link here, /dev/stdout's magic one too
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(dir()),
        // `/dev/stdout`, or the file stdout was sent to: written through
        // stdout itself, so that the report cannot land in the middle
        Ok(m) if is_stdout(&m) => Ok(Target::Stdout),
        Ok(m) if m.is_file() => resolve(path).map(Target::File),
        Ok(m) if is_stream(&m) => Ok(Target::Stream(path.to_path_buf())),
        Ok(_) => Err("must name a file, a FIFO or a character device, not a block device or socket".into()),
        // not made yet (or not reachable: the write will say why)
        Err(_) => resolve(path).and_then(|end| end.file_name().map(|_| Target::File(end.clone())).ok_or_else(dir)),
    }
}

/// Windows' reserved device names (NUL, CON, COM1, ...), alone or as
/// `\\.\NAME`: they name a device, not a file, and a
/// rename over one fails; written in place, as /dev/null is on Linux.
#[cfg_attr(not(windows), allow(dead_code))]
pub fn is_windows_device(path: &Path) -> bool {
    let text = path.to_string_lossy();
    let name = text.strip_prefix(r"\\.\").unwrap_or(&text).to_ascii_uppercase();
    let numbered =
        |p: &str| name.strip_prefix(p).is_some_and(|n| n.len() == 1 && matches!(n.as_bytes()[0], b'1'..=b'9'));
    matches!(name.as_str(), "NUL" | "CON" | "PRN" | "AUX") || numbered("COM") || numbered("LPT")
}

#[cfg(unix)]
fn is_stream(m: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt;
    m.file_type().is_char_device() || m.file_type().is_fifo()
}

/// Whether `m` is the file our stdout is (an fstat of a copy of fd 1).
#[cfg(unix)]
fn is_stdout(m: &std::fs::Metadata) -> bool {
    use std::os::fd::AsFd;
    use std::os::unix::fs::MetadataExt;
    let Ok(fd) = std::io::stdout().as_fd().try_clone_to_owned() else { return false };
    std::fs::File::from(fd).metadata().is_ok_and(|s| (s.dev(), s.ino()) == (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn is_stdout(_: &std::fs::Metadata) -> bool {
    false
}

#[cfg(not(unix))]
fn is_stream(_: &std::fs::Metadata) -> bool {
    false
}

/// `path` with the symlinks at its end followed, however many deep (a
/// link to a link to a file not made yet ends at that file's path).
fn resolve(path: &Path) -> Result<PathBuf, String> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let is_link = std::fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink());
        if !is_link {
            return Ok(p);
        }
        let to = std::fs::read_link(&p).map_err(|e| format!("could not follow the symlink: {e}"))?;
        // a relative link is relative to the directory it lies in
        p = p.parent().unwrap_or(Path::new("")).join(to);
    }
    Err(format!("could not follow the symlink: more than {MAX_LINKS} links deep"))
}

/// The file a target (or an input) is.
pub fn identity(target: &Target) -> Identity {
    match target {
        Target::Stdout => Identity::Stdout,
        Target::File(p) | Target::Stream(p) => identity_of(p),
    }
}

/// The file at `path`, symlinks followed.
pub fn identity_of(path: &Path) -> Identity {
    #[cfg(unix)]
    if let Ok(m) = std::fs::metadata(path) {
        use std::os::unix::fs::MetadataExt;
        return Identity::Node(m.dev(), m.ino());
    }
    // elsewhere an existing file is its real path (on Windows the case and
    // the short names as the file system has them)
    #[cfg(not(unix))]
    if let Ok(real) = path.canonicalize() {
        return Identity::Path(real);
    }
    let parent = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().unwrap_or_default();
    Identity::Path(parent.canonicalize().map(|d| d.join(name)).unwrap_or_else(|_| path.to_path_buf()))
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("polyturn-target-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_symlink_resolves_to_the_file_it_names_and_a_device_is_written_in_place() {
        let d = dir("classify");
        symlink("b", d.join("a")).unwrap();
        symlink("c.svg", d.join("b")).unwrap();
        assert_eq!(classify(&d.join("a")), Ok(Target::File(d.join("c.svg"))));
        assert_eq!(classify(Path::new("/dev/full")), Ok(Target::Stream("/dev/full".into())));
        assert_eq!(classify(Path::new("-")), Ok(Target::Stdout));
        assert!(classify(&d).unwrap_err().contains("not a directory"));
        symlink(&d, d.join("to-dir")).unwrap();
        assert!(classify(&d.join("to-dir")).unwrap_err().contains("not a directory"));
        symlink("loop", d.join("loop")).unwrap();
        assert!(classify(&d.join("loop")).unwrap_err().contains("more than 40 links"));
    }

    #[test]
    fn windows_device_names_are_devices_in_any_case_and_nothing_else_is() {
        for dev in ["NUL", "nul", "CON", r"\\.\NUL", "COM1", "lpt9", "Aux"] {
            assert!(is_windows_device(Path::new(dev)), "{dev}");
        }
        for file in ["NUL.svg", "COM10", "COM0", "CONSOLE", r"C:\NUL\x.svg", "nul/x", "", "-"] {
            assert!(!is_windows_device(Path::new(file)), "{file}");
        }
    }

    #[test]
    fn one_file_has_one_identity_however_it_is_spelt() {
        let d = dir("identity");
        std::fs::write(d.join("f"), "x").unwrap();
        std::fs::hard_link(d.join("f"), d.join("hard")).unwrap();
        symlink("f", d.join("soft")).unwrap();
        let f = identity_of(&d.join("f"));
        for other in [d.join("hard"), d.join("soft"), d.join(".").join("f")] {
            assert_eq!(identity_of(&other), f, "{}", other.display());
        }
        assert_eq!(identity_of(&d.join("new")), identity_of(&d.join("./new")));
        assert_ne!(identity_of(&d.join("new")), f);
    }
}
