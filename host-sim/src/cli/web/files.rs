//! Which file a URL names: only a regular file whose real path (links
//! resolved) lies inside the page's folder, with no name starting with '.'
//! on the way, and judged again on the opened file, so that a link to
//! /dev/zero or a FIFO put in the folder is refused rather than read.

use super::request::BAD_REQUEST;
use std::fs::File;
use std::path::{Component, Path, PathBuf};

pub const NOT_FOUND: &str = "404 Not Found";

/// A body to send: a file from the page's folder, or bytes carried in the
/// binary (`site`).
pub enum Body {
    File(File),
    Bytes(&'static [u8]),
}

/// What to send: its body, length and Content-Type.
pub struct Found {
    pub body: Body,
    pub len: u64,
    pub kind: &'static str,
}

/// The file `target` (`/path?query`) names under `root`, which must be
/// canonical; Err is the status line of the refusal.
pub fn find(root: &Path, target: &str) -> Result<Found, &'static str> {
    let rel = relative(target)?;
    let real = std::fs::canonicalize(root.join(rel)).map_err(|_| NOT_FOUND)?;
    let inside = real.strip_prefix(root).map_err(|_| NOT_FOUND)?;
    // a link inside may name a dotfile inside: its real name counts too
    if !inside.components().all(|c| matches!(c, Component::Normal(n) if !n.as_encoded_bytes().starts_with(b"."))) {
        return Err(NOT_FOUND);
    }
    // asked before opening, so that no device or FIFO is ever opened...
    if !std::fs::metadata(&real).is_ok_and(|m| m.is_file()) {
        return Err(NOT_FOUND);
    }
    let file = open(&real).map_err(|_| NOT_FOUND)?;
    // ...and asked again of what was opened, in case the name was swapped
    let meta = file.metadata().map_err(|_| NOT_FOUND)?;
    if !meta.is_file() {
        return Err(NOT_FOUND);
    }
    Ok(Found { body: Body::File(file), len: meta.len(), kind: content_type(&real) })
}

/// Opens for reading without waiting: O_NONBLOCK makes opening a FIFO
/// return at once instead of blocking until a writer comes.
fn open(path: &Path) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    options.open(path)
}

/// The relative path a target names: the query dropped, each segment
/// percent-decoded, `/` and a trailing `/` naming index.html. A segment
/// that is not a plain name, or starts with '.', is not found; a broken
/// escape or a name that is not UTF-8 is a bad request.
pub fn relative(target: &str) -> Result<PathBuf, &'static str> {
    let path = target.split(['?', '#']).next().unwrap_or_default();
    let mut rel = PathBuf::new();
    for segment in path.split('/').filter(|s| !s.is_empty()) {
        let name = decode(segment).ok_or(BAD_REQUEST)?;
        let plain = Path::new(&name).components().eq([Component::Normal(std::ffi::OsStr::new(&name))]);
        if !plain || name.starts_with('.') || name.contains('\0') {
            return Err(NOT_FOUND);
        }
        rel.push(name);
    }
    if path.ends_with('/') || rel.as_os_str().is_empty() {
        rel.push("index.html");
    }
    Ok(rel)
}

/// `%XX` escapes decoded; None for a broken escape or bytes not UTF-8.
fn decode(segment: &str) -> Option<String> {
    let bytes = segment.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while let Some(&b) = bytes.get(i) {
        if b == b'%' {
            let digit = |at: usize| bytes.get(at).and_then(|&d| char::from(d).to_digit(16));
            // to_digit, not from_str_radix: that one takes "+1" too
            out.push((digit(i + 1)? * 16 + digit(i + 2)?) as u8);
            i += 3;
        } else {
            out.push(b);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// WebAssembly must be served as application/wasm for streaming compile,
/// and modules as JavaScript, or the browser refuses them.
pub fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("wasm") => "application/wasm",
        Some("css") => "text/css; charset=utf-8",
        Some("svg") => "image/svg+xml",
        Some("png") => "image/png",
        Some("json") => "application/json",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_plain_names_without_a_leading_dot_make_a_path() {
        let ok = |t: &str| relative(t).map(|p| p.to_string_lossy().into_owned());
        assert_eq!(ok("/"), Ok("index.html".into()));
        assert_eq!(ok("/pkg/a.js?v=2"), Ok("pkg/a.js".into()));
        assert_eq!(ok("/docs/"), Ok("docs/index.html".into()));
        assert_eq!(ok("/a%20b.js"), Ok("a b.js".into()));
        // leading and doubled slashes go: `//etc/passwd` names a file in the folder
        assert_eq!(ok("//etc//passwd"), Ok("etc/passwd".into()));
        for bad in ["/../etc/passwd", "/pkg/../../x", "/./a", "/.git/config", "/%2e%2e/x", "/a%2fb", "/a%00"] {
            assert_eq!(ok(bad), Err(NOT_FOUND), "{bad}");
        }
        for broken in ["/a%2", "/a%zz", "/%ff", "/%+1"] {
            assert_eq!(ok(broken), Err(BAD_REQUEST), "{broken}");
        }
    }

    #[test]
    fn webassembly_and_modules_get_the_types_the_browser_needs() {
        assert_eq!(content_type(Path::new("x/polyturn_web_bg.wasm")), "application/wasm");
        assert_eq!(content_type(Path::new("app.js")), "text/javascript; charset=utf-8");
        assert_eq!(content_type(Path::new("index.html")), "text/html; charset=utf-8");
        assert_eq!(content_type(Path::new("style.css")), "text/css; charset=utf-8");
        assert_eq!(content_type(Path::new("icon.svg")), "image/svg+xml");
        assert_eq!(content_type(Path::new("noext")), "application/octet-stream");
    }
}
