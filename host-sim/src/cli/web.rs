//! `polyturn web`: serves the page (`web/www`, built by `bash web/build`,
//! or the copy a release `polyturn` carries) on localhost and opens the
//! browser. WebSerial and WebUSB need a secure context, and
//! http://127.0.0.1 is one; the same files work from any static host. Only
//! GET and HEAD of the page's regular files are answered, and of the
//! firmware image a release `polyturn` carries. With `--board PORT` the
//! board's console is opened here and relayed to the pages over a
//! WebSocket (`relay.rs`), for browsers without WebSerial; `--listen ADDR`
//! serves beyond this machine, to holders of the token printed at start.

mod access;
mod files;
mod relay;
mod relay_line;
mod request;
mod server;
mod site;
mod socket;
mod timed;

use super::carried;
use super::errors::{escaped, CliError, CliResult};
use relay::Relay;
use site::{Page, Site};
use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, TcpListener};
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
    #[arg(long, value_name = "PORT", default_value = "8177", value_parser = super::values::tcp_port)]
    pub port: u16,
    /// Print the address but do not open a browser
    #[arg(long)]
    pub no_open: bool,
    /// The board's serial port (COM5 on Windows), opened here and relayed
    /// to the page's Device view, for any browser (dfu is not relayed)
    #[arg(long, value_name = "PORT")]
    pub board: Option<String>,
    /// Serve on this address instead of 127.0.0.1 (0.0.0.0: every network),
    /// beyond this machine; every request then needs the token printed at start
    #[arg(long, value_name = "ADDR", value_parser = super::values::ip_address)]
    pub listen: Option<IpAddr>,
}

pub fn run(a: WebArgs) -> CliResult<String> {
    let (page, shown) = which_page(a.dir, carried::page())?;
    let ip = a.listen.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    let mut site = Site::new(page, carried::firmware());
    if a.listen.is_some() {
        site.access.token = Some(access::new_token().map_err(|e| CliError::flag("listen", e))?);
    }
    if let Some(port) = &a.board {
        site.relay = Some(Relay::start(port, relay::serial(port.clone())).map_err(|e| CliError::flag("board", e))?);
    }
    let listener = TcpListener::bind((ip, a.port)).map_err(|e| {
        let (flag, addr) = if a.listen.is_some() { ("listen", ip.to_string()) } else { ("port", "127.0.0.1".into()) };
        CliError::flag(flag, format!("cannot listen on {addr}:{}: {e}", a.port))
    })?;
    let port = listener.local_addr().map_or(a.port, |s| s.port());
    let url = address(ip, port, site.access.token.as_deref());
    // the address goes out before serving starts: a test reads it here
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "polyturn web: serving {shown} at {url} (Ctrl-C to stop)");
    if ip.is_unspecified() {
        let elsewhere = url.replace("127.0.0.1", "THIS-MACHINE");
        let _ = writeln!(out, "polyturn web: from another machine: {elsewhere} (THIS-MACHINE: this one's name or address on your network)");
    }
    if let Some(r) = &site.relay {
        let _ = writeln!(out, "polyturn web: the board on {} is relayed to the page's Device view; one page has control, the others watch; dfu is not relayed (flash on this machine)", escaped(&r.port));
    }
    let _ = out.flush();
    drop(out);
    let site = Arc::new(site);
    if !a.no_open {
        if let Err(e) = webbrowser::open(&url) {
            eprintln!("polyturn web: could not open a browser ({e}); open {url} yourself");
        }
    }
    server::serve(&listener, &site, server::LIMITS);
    Ok(String::new())
}

/// The page's address: loopback for this machine when listening on every
/// network, with the token when one is asked.
fn address(ip: IpAddr, port: u16, token: Option<&str>) -> String {
    let host = match ip {
        ip if ip.is_unspecified() => "127.0.0.1".to_string(),
        IpAddr::V6(v6) => format!("[{v6}]"),
        IpAddr::V4(v4) => v4.to_string(),
    };
    let query = token.map(|t| format!("?token={t}")).unwrap_or_default();
    format!("http://{host}:{port}/{query}")
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
        let a = WebArgs { dir: Some(d.clone()), port: 0, no_open: true, board: None, listen: None };
        let e = run(a).unwrap_err().0;
        let _ = std::fs::remove_dir_all(&d);
        assert!(e.starts_with(&format!("--dir '{}' has no pkg/polyturn_web_bg.wasm", d.display())), "{e}");
        assert!(e.contains("bash web/build"), "{e}");
    }

    #[test]
    fn a_missing_page_folder_is_refused_as_missing() {
        let a = WebArgs {
            dir: Some(PathBuf::from("/nonexistent-page")),
            port: 0,
            no_open: true,
            board: None,
            listen: None,
        };
        let e = run(a).unwrap_err().0;
        assert_eq!(e, "--dir '/nonexistent-page' does not exist: build the page with `bash web/build`");
    }

    #[test]
    fn the_address_printed_holds_the_token_and_names_loopback_for_every_network() {
        let any = IpAddr::V4(Ipv4Addr::UNSPECIFIED);
        assert_eq!(address(any, 8177, Some("ab12")), "http://127.0.0.1:8177/?token=ab12");
        assert_eq!(address("192.0.2.7".parse().unwrap(), 80, Some("ab12")), "http://192.0.2.7:80/?token=ab12");
        assert_eq!(address("::1".parse().unwrap(), 80, None), "http://[::1]:80/");
    }

    #[test]
    fn a_board_that_cannot_be_opened_is_refused_naming_the_flag_before_listening() {
        let page = std::env::temp_dir().join(format!("polyturn-web-board-{}", std::process::id()));
        std::fs::create_dir_all(page.join("pkg")).unwrap();
        std::fs::write(page.join(WASM), b"\0asm").unwrap();
        let a = WebArgs {
            dir: Some(page.clone()),
            port: 0,
            no_open: true,
            board: Some("/nonexistent-port".into()),
            listen: None,
        };
        let e = run(a).unwrap_err().0;
        let _ = std::fs::remove_dir_all(&page);
        assert!(e.starts_with("--board cannot open /nonexistent-port: "), "{e}");
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
