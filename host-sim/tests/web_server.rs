//! `polyturn web`'s server from outside: the real binary on a free loopback
//! port, spoken to over plain TCP. Every wait has a deadline, so a server
//! that hangs fails a test instead of stalling it.
#![cfg(all(unix, feature = "device"))]

#[path = "web_server/harness.rs"]
mod harness;

use harness::{read_reply, refused, Page, Reply, Server, POLYTURN, REPLY_WAIT, WASM};
use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, TcpStream};
use std::process::Command;
use std::time::{Duration, Instant};

#[test]
fn a_symlink_inside_the_folder_does_not_lead_out_of_it() {
    let page = Page::new("symlink");
    std::os::unix::fs::symlink("/etc", page.0.join("dirlink")).unwrap();
    std::os::unix::fs::symlink("/etc/passwd", page.0.join("passwd")).unwrap();
    std::os::unix::fs::symlink("index.html", page.0.join("alias.html")).unwrap();
    let server = Server::start(&page.0);
    for path in ["/dirlink/passwd", "/passwd", "/dirlink/hostname"] {
        let r = server.get(path);
        assert_eq!(r.status, 404, "{path}: {r:?}");
        assert!(!String::from_utf8_lossy(&r.body).contains("root:"), "{path} leaked /etc");
    }
    // a link that stays inside the folder is still a page file
    assert_eq!(server.get("/alias.html").body, b"<p>page</p>");
}

#[test]
fn dotfiles_and_dot_folders_are_not_served() {
    let page = Page::new("dotfiles");
    std::fs::write(page.0.join(".env"), "SECRET=1").unwrap();
    std::fs::create_dir_all(page.0.join(".git")).unwrap();
    std::fs::write(page.0.join(".git/config"), "[core]").unwrap();
    std::os::unix::fs::symlink(".env", page.0.join("env.txt")).unwrap();
    let server = Server::start(&page.0);
    for path in ["/.env", "/.git/config", "/%2egit/config", "/pkg/../.env", "/env.txt"] {
        let r = server.get(path);
        assert_eq!(r.status, 404, "{path}: {r:?}");
    }
}

#[test]
fn past_the_connection_bound_a_client_gets_503_and_threads_stay_bounded() {
    let page = Page::new("bound");
    let server = Server::start(&page.0);
    // idle clients that never send a byte, more than any sane bound
    let idle: Vec<TcpStream> = (0..100).map(|_| server.connect()).collect();
    let r = server.get("/");
    assert_eq!(r.status, 503, "{r:?}");
    assert!(server.threads() <= 40, "{} threads for 100 idle connections", server.threads());
    drop(idle);
    // the slots come back once the idle clients are gone
    let end = Instant::now() + REPLY_WAIT;
    while server.get("/").status != 200 {
        assert!(Instant::now() < end, "the server stayed full after the idle clients left");
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn a_browsers_parallel_module_requests_are_all_answered() {
    let page = Page::new("parallel");
    let server = Server::start(&page.0);
    // what Chromium does with the page's modules, twice over
    let replies: Vec<Reply> = std::thread::scope(|s| {
        let asks: Vec<_> = (0..12).map(|_| s.spawn(|| server.get("/pkg/polyturn_web.js"))).collect();
        asks.into_iter().map(|a| a.join().unwrap()).collect()
    });
    for r in &replies {
        assert_eq!((r.status, r.body.as_slice()), (200, &b"export {};"[..]), "{r:?}");
    }
}

#[test]
fn a_client_trickling_its_request_is_cut_off_at_the_head_deadline() {
    let page = Page::new("trickle");
    let server = Server::start(&page.0);
    let mut s = server.connect();
    s.set_read_timeout(Some(Duration::from_secs(1))).unwrap();
    let start = Instant::now();
    // one byte a second: no single read waits long, the whole head does
    let trickle = b"GET / HTTP/1.1\r\nX-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
    for &b in trickle {
        let _ = s.write(&[b]);
        let mut buf = [0u8; 256];
        match s.read(&mut buf) {
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            // closed, or answered (408): cut off
            _ => break,
        }
        assert!(start.elapsed() < Duration::from_secs(14), "a trickling client held its thread past 14 s");
    }
    let took = start.elapsed();
    assert!(took >= Duration::from_secs(8) && took < Duration::from_secs(14), "cut off after {took:?}");
}

#[test]
fn a_fifo_in_the_folder_is_refused_without_blocking_the_server() {
    let page = Page::new("fifo");
    let ok = Command::new("mkfifo").arg(page.0.join("pipe.js")).status().unwrap();
    assert!(ok.success());
    let server = Server::start(&page.0);
    let start = Instant::now();
    assert_eq!(server.get("/pipe.js").status, 404);
    assert!(start.elapsed() < Duration::from_secs(2), "a FIFO took {:?}", start.elapsed());
    assert_eq!(server.get("/").status, 200);
}

#[test]
fn a_link_to_an_endless_device_is_refused_not_read() {
    let page = Page::new("devzero");
    std::os::unix::fs::symlink("/dev/zero", page.0.join("zero.wasm")).unwrap();
    let server = Server::start(&page.0);
    let start = Instant::now();
    assert_eq!(server.get("/zero.wasm").status, 404);
    assert!(start.elapsed() < Duration::from_secs(2), "/dev/zero took {:?}", start.elapsed());
}

#[test]
fn head_gets_the_headers_of_get_and_no_body() {
    let page = Page::new("head");
    let server = Server::start(&page.0);
    let raw = server.ask(b"HEAD /pkg/polyturn_web_bg.wasm HTTP/1.1\r\nHost: x\r\n\r\n");
    let r = Reply::parse(&raw);
    assert_eq!(r.status, 200, "{r:?}");
    assert_eq!(r.header("content-type"), Some("application/wasm"));
    assert_eq!(r.header("content-length"), Some(WASM.len().to_string().as_str()));
    assert!(r.body.is_empty(), "HEAD sent a body: {:?}", r.body);
    let missing = Reply::parse(&server.ask(b"HEAD /missing HTTP/1.1\r\n\r\n"));
    assert_eq!(missing.status, 404);
    assert!(missing.body.is_empty());
}

#[test]
fn a_request_ended_by_bare_line_feeds_is_answered() {
    let page = Page::new("lflf");
    let server = Server::start(&page.0);
    let r = Reply::parse(&server.ask(b"GET /style.css HTTP/1.1\nHost: x\n\n"));
    assert_eq!((r.status, r.body.as_slice()), (200, &b"p {}"[..]), "{r:?}");
}

#[test]
fn each_page_file_is_served_whole_with_the_type_the_browser_needs() {
    let page = Page::new("types");
    let server = Server::start(&page.0);
    for (path, kind) in [
        ("/", "text/html; charset=utf-8"),
        ("/pkg/polyturn_web.js", "text/javascript; charset=utf-8"),
        ("/pkg/polyturn_web_bg.wasm", "application/wasm"),
        ("/style.css", "text/css; charset=utf-8"),
        ("/icon.svg", "image/svg+xml"),
    ] {
        let r = server.get(path);
        assert_eq!(r.status, 200, "{path}: {r:?}");
        assert_eq!(r.header("content-type"), Some(kind), "{path}");
        let file = if path == "/" { "index.html" } else { &path[1..] };
        assert_eq!(r.body, std::fs::read(page.0.join(file)).unwrap(), "{path}");
        assert_eq!(r.header("content-length"), Some(r.body.len().to_string().as_str()), "{path}");
    }
}

#[test]
fn a_malformed_request_gets_400_and_another_method_405() {
    let page = Page::new("malformed");
    let server = Server::start(&page.0);
    for raw in
        [&b"GARBAGE\r\n\r\n"[..], b"GET / FTP/1.0\r\n\r\n", b"GET http://x/ HTTP/1.1\r\n\r\n", b"\xff\xfe\r\n\r\n"]
    {
        let r = Reply::parse(&server.ask(raw));
        assert_eq!(r.status, 400, "{raw:?}: {r:?}");
    }
    let r = Reply::parse(&server.ask(b"POST / HTTP/1.1\r\n\r\n"));
    assert_eq!(r.status, 405, "{r:?}");
    assert_eq!(r.header("allow"), Some("GET, HEAD"));
}

#[test]
fn an_oversized_request_head_is_refused_with_431() {
    let page = Page::new("oversized");
    let server = Server::start(&page.0);
    let mut s = server.connect();
    let mut head = b"GET / HTTP/1.1\r\nX-Big: ".to_vec();
    head.resize(64 * 1024, b'a');
    let _ = s.write_all(&head);
    let _ = s.shutdown(Shutdown::Write);
    let r = Reply::parse(&read_reply(&mut s, REPLY_WAIT));
    assert_eq!(r.status, 431, "{r:?}");
}

#[test]
fn a_percent_encoded_name_is_the_file_it_names() {
    let page = Page::new("percent");
    std::fs::write(page.0.join("a b.js"), "x").unwrap();
    let server = Server::start(&page.0);
    assert_eq!(server.get("/a%20b.js").body, b"x");
    for bad in ["/a%2", "/a%zz.js", "/%ff.js"] {
        assert_eq!(server.get(bad).status, 400, "{bad}");
    }
    assert_eq!(server.get("/pkg%2fpolyturn_web.js").status, 404);
}

#[test]
fn a_bad_dir_is_refused_saying_what_is_wrong_with_it() {
    let page = Page::new("baddir");
    let missing = page.0.join("nope");
    let (code, err) = refused(&missing);
    assert_eq!(code, Some(2));
    assert_eq!(
        err,
        format!("error: --dir '{}' does not exist: build the page with `bash web/build`\n", missing.display())
    );
    let (code, err) = refused(&page.0.join("index.html"));
    assert_eq!(code, Some(2));
    assert!(err.starts_with("error: --dir '") && err.ends_with("index.html' is not a folder\n"), "{err}");
    std::fs::remove_file(page.0.join("pkg/polyturn_web_bg.wasm")).unwrap();
    let (code, err) = refused(&page.0);
    assert_eq!(code, Some(2));
    assert!(err.contains("has no pkg/polyturn_web_bg.wasm: build the page first with `bash web/build`"), "{err}");
    // a wasm that links out of the folder would not be served: no page
    std::os::unix::fs::symlink("/etc/passwd", page.0.join("pkg/polyturn_web_bg.wasm")).unwrap();
    let (code, err) = refused(&page.0);
    assert_eq!(code, Some(2));
    assert!(err.contains("has no pkg/polyturn_web_bg.wasm"), "{err}");
}

#[test]
fn web_help_names_every_flag_and_what_is_served() {
    let out = Command::new(POLYTURN).args(["web", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{help}");
    for needle in [
        "--dir <DIR>",
        "[default: the page a release polyturn carries, else web/www]",
        "--port <PORT>",
        "[default: 8177]",
        "--no-open",
        "127.0.0.1",
    ] {
        assert!(help.contains(needle), "missing {needle}: {help}");
    }
}
