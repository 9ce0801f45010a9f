//! `polyturn web`: serves the page (`web/www`, built by `bash web/build`,
//! or the copy a release `polyturn` carries) on localhost and opens the
//! browser. WebSerial and WebUSB need a secure context, and
//! http://127.0.0.1 is one; the same files work from any static host. Only
//! GET and HEAD of the page's regular files are answered, and of the
//! firmware image a release `polyturn` carries.

mod files;
mod request;
mod server;
mod site;
mod timed;

use super::carried;
use super::errors::{escaped, CliError, CliResult};
use site::{Page, Site};
use std::io::Write;
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The wasm-bindgen output the page cannot start without.
const WASM: &str = "pkg/polyturn_web_bg.wasm";

#[derive(clap::Args, Debug)]
pub struct WebArgs {
    /// The page's folder (built by `bash web/build`) [default: the page a release polyturn carries, else web/www]
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
    /// Port on 127.0.0.1 (0: any free port; the address is printed)
    #[arg(long, value_name = "PORT", default_value = "8177", value_parser = clap::value_parser!(u16))]
    pub port: u16,
    /// Print the address but do not open a browser
    #[arg(long)]
    pub no_open: bool,
}

pub fn run(a: WebArgs) -> CliResult<String> {
    let (page, shown) = which_page(a.dir, carried::page())?;
    let site = Arc::new(Site { page, firmware: carried::firmware() });
    let listener = TcpListener::bind(("127.0.0.1", a.port))
        .map_err(|e| CliError::flag("port", format!("cannot listen on 127.0.0.1:{}: {e}", a.port)))?;
    let port = listener.local_addr().map_or(a.port, |s| s.port());
    let url = format!("http://127.0.0.1:{port}/");
    // the address goes out before serving starts: a test reads it here
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "polyturn web: serving {shown} at {url} (Ctrl-C to stop)");
    let _ = out.flush();
    drop(out);
    if !a.no_open {
        if let Err(e) = webbrowser::open(&url) {
            eprintln!("polyturn web: could not open a browser ({e}); open {url} yourself");
        }
    }
    server::serve(&listener, &site, server::LIMITS);
    Ok(String::new())
}

/// The page from DIR if given, else the carried one, else web/www; and
/// how it is named when serving starts.
fn which_page(dir: Option<PathBuf>, carried: Option<carried::Page>) -> CliResult<(Page, String)> {
    match (dir, carried) {
        (None, Some(files)) => Ok((Page::Carried(files), "the page this polyturn carries".into())),
        (dir, _) => {
            let dir = dir.unwrap_or_else(|| PathBuf::from("web/www"));
            Ok((Page::Folder(page_root(&dir)?), escaped(&dir.display().to_string())))
        }
    }
}

/// The page's folder, canonical (the server compares every file's real
/// path with it), refused unless it holds a servable wasm.
fn page_root(dir: &Path) -> CliResult<PathBuf> {
    let shown = escaped(&dir.display().to_string());
    let root = std::fs::canonicalize(dir).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => {
            CliError::flag("dir", format!("'{shown}' does not exist: build the page with `bash web/build`"))
        }
        _ => CliError::flag("dir", format!("'{shown}' cannot be read ({})", escaped(&e.to_string()))),
    })?;
    if !root.is_dir() {
        return Err(CliError::flag("dir", format!("'{shown}' is not a folder")));
    }
    // the same test the server applies: a wasm it would refuse is no page
    if files::find(&root, &format!("/{WASM}")).is_err() {
        return Err(CliError::flag(
            "dir",
            format!("'{shown}' has no {WASM}: build the page first with `bash web/build`"),
        ));
    }
    Ok(root)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unbuilt_page_is_refused_naming_the_build_command() {
        let d = std::env::temp_dir().join(format!("polyturn-web-unbuilt-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let a = WebArgs { dir: Some(d.clone()), port: 0, no_open: true };
        let e = run(a).unwrap_err().0;
        let _ = std::fs::remove_dir_all(&d);
        assert!(e.starts_with(&format!("--dir '{}' has no pkg/polyturn_web_bg.wasm", d.display())), "{e}");
        assert!(e.contains("bash web/build"), "{e}");
    }

    #[test]
    fn a_missing_page_folder_is_refused_as_missing() {
        let a = WebArgs { dir: Some(PathBuf::from("/nonexistent-page")), port: 0, no_open: true };
        let e = run(a).unwrap_err().0;
        assert_eq!(e, "--dir '/nonexistent-page' does not exist: build the page with `bash web/build`");
    }

    #[test]
    fn the_carried_page_is_served_unless_a_folder_is_given() {
        const FILES: carried::Page = &[("index.html", b"x")];
        let (page, shown) = which_page(None, Some(FILES)).unwrap();
        assert!(matches!(page, Page::Carried(f) if f == FILES) && shown == "the page this polyturn carries");
        // --dir overrides, and is checked as ever
        let e = which_page(Some(PathBuf::from("/nonexistent-page")), Some(FILES)).err().unwrap().0;
        assert!(e.starts_with("--dir '/nonexistent-page' does not exist"), "{e}");
        let e = which_page(None, None).err().unwrap().0;
        assert!(e.starts_with("--dir 'web/www' "), "{e}");
    }
}
