//! `polyturn web`: serves the page (`web/www`, built by `bash web/build`)
//! on localhost and opens the browser. WebSerial and WebUSB need a secure
//! context, and http://127.0.0.1 is one; the same files work from any
//! static host. Only GET of files inside the page's folder is answered.

use super::errors::{escaped, CliError, CliResult};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Component, Path, PathBuf};
use std::time::Duration;

/// The longest request head taken (the page's are a few hundred bytes).
const HEAD_MAX: usize = 16 * 1024;
/// The wasm-bindgen output the page cannot start without.
const WASM: &str = "pkg/polyturn_web_bg.wasm";

#[derive(clap::Args, Debug)]
pub struct WebArgs {
    /// The page's folder (built by `bash web/build`)
    #[arg(long, value_name = "DIR", default_value = "web/www")]
    pub dir: PathBuf,
    /// Port on 127.0.0.1 (0: any free port; the address is printed)
    #[arg(long, value_name = "PORT", default_value = "8177", value_parser = clap::value_parser!(u16))]
    pub port: u16,
    /// Print the address but do not open a browser
    #[arg(long)]
    pub no_open: bool,
}

pub fn run(a: WebArgs) -> CliResult<String> {
    if !a.dir.join(WASM).is_file() {
        return Err(CliError::flag(
            "dir",
            format!(
                "'{}' has no {WASM}: build the page first with `bash web/build`",
                escaped(&a.dir.display().to_string())
            ),
        ));
    }
    let listener = TcpListener::bind(("127.0.0.1", a.port))
        .map_err(|e| CliError::flag("port", format!("cannot listen on 127.0.0.1:{}: {e}", a.port)))?;
    let port = listener.local_addr().map_or(a.port, |s| s.port());
    let url = format!("http://127.0.0.1:{port}/");
    // the address goes out before serving starts: a test reads it here
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "polyturn web: serving {} at {url} (Ctrl-C to stop)", a.dir.display());
    let _ = out.flush();
    drop(out);
    if !a.no_open {
        if let Err(e) = webbrowser::open(&url) {
            eprintln!("polyturn web: could not open a browser ({e}); open {url} yourself");
        }
    }
    for stream in listener.incoming().flatten() {
        let dir = a.dir.clone();
        std::thread::spawn(move || serve(&dir, stream));
    }
    Ok(String::new())
}

/// One request per connection (HTTP/1.1 with `Connection: close`), every
/// read bounded in time and size. (tiny_http was tried first: with
/// Chromium's six parallel module requests it left some unanswered.)
fn serve(dir: &Path, mut stream: TcpStream) {
    let _ = stream.set_read_timeout(Some(Duration::from_secs(5)));
    let _ = stream.set_write_timeout(Some(Duration::from_secs(30)));
    let mut head = Vec::new();
    let mut buf = [0u8; 1024];
    while !head.windows(4).any(|w| w == b"\r\n\r\n") && head.len() < HEAD_MAX {
        match stream.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => head.extend_from_slice(&buf[..n]),
        }
    }
    let line = String::from_utf8_lossy(head.split(|&b| b == b'\r').next().unwrap_or(&[])).into_owned();
    let (status, kind, body) = answer(dir, &line);
    let header = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-cache\r\nConnection: close\r\n\r\n",
        body.len()
    );
    let _ = stream.write_all(header.as_bytes()).and_then(|()| stream.write_all(&body));
}

/// The reply to a request line (`GET /path HTTP/1.1`): status, type, body.
pub fn answer(dir: &Path, request_line: &str) -> (&'static str, &'static str, Vec<u8>) {
    let mut parts = request_line.split(' ');
    let (method, url) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let not_found = ("404 Not Found", "text/plain", b"not found".to_vec());
    if method != "GET" {
        return ("405 Method Not Allowed", "text/plain", b"only GET".to_vec());
    }
    let Some(path) = local_path(dir, url) else { return not_found };
    match std::fs::read(&path) {
        Ok(bytes) => ("200 OK", content_type(&path), bytes),
        Err(_) => not_found,
    }
}

/// The file a URL names inside `dir`: the query dropped, `/` is
/// index.html, and nothing but plain names (no `..`, no root, no drive).
pub fn local_path(dir: &Path, url: &str) -> Option<PathBuf> {
    let path = url.split(['?', '#']).next().unwrap_or("");
    let rel = path.trim_start_matches('/');
    let rel = if rel.is_empty() || rel.ends_with('/') { format!("{rel}index.html") } else { rel.to_string() };
    let rel = Path::new(&rel);
    if !rel.components().all(|c| matches!(c, Component::Normal(_))) {
        return None;
    }
    Some(dir.join(rel))
}

/// WebAssembly must be served as application/wasm for streaming compile.
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
    fn only_plain_names_inside_the_folder_are_served() {
        let d = Path::new("/srv/page");
        assert_eq!(local_path(d, "/"), Some(d.join("index.html")));
        assert_eq!(local_path(d, "/pkg/a.js?v=2"), Some(d.join("pkg/a.js")));
        assert_eq!(local_path(d, "/docs/"), Some(d.join("docs/index.html")));
        // leading slashes all go: `//etc/passwd` names a file in the folder
        assert_eq!(local_path(d, "//etc/passwd"), Some(d.join("etc/passwd")));
        for bad in ["/../etc/passwd", "/pkg/../../x", "/./a", "/a/../../b"] {
            assert_eq!(local_path(d, bad), None, "{bad}");
        }
    }

    #[test]
    fn a_request_gets_the_file_or_a_plain_refusal() {
        let d = std::env::temp_dir().join(format!("polyturn-web-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("index.html"), "<p>hi</p>").unwrap();
        assert_eq!(answer(&d, "GET / HTTP/1.1"), ("200 OK", "text/html; charset=utf-8", b"<p>hi</p>".to_vec()));
        assert_eq!(answer(&d, "GET /missing.js HTTP/1.1").0, "404 Not Found");
        assert_eq!(answer(&d, "GET /../index.html HTTP/1.1").0, "404 Not Found");
        assert_eq!(answer(&d, "POST / HTTP/1.1").0, "405 Method Not Allowed");
        assert_eq!(answer(&d, "").0, "405 Method Not Allowed");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn webassembly_is_served_as_application_wasm() {
        assert_eq!(content_type(Path::new("x/polyturn_web_bg.wasm")), "application/wasm");
        assert_eq!(content_type(Path::new("app.js")), "text/javascript; charset=utf-8");
        assert_eq!(content_type(Path::new("noext")), "application/octet-stream");
    }

    #[test]
    fn an_unbuilt_page_is_refused_naming_the_build_command() {
        let a = WebArgs { dir: PathBuf::from("/nonexistent-page"), port: 0, no_open: true };
        let e = run(a).unwrap_err().0;
        assert!(e.starts_with("--dir '/nonexistent-page' has no pkg/polyturn_web_bg.wasm"), "{e}");
        assert!(e.contains("bash web/build"), "{e}");
    }
}
