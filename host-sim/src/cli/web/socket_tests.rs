//! The relay over real sockets, served by the server's own connection
//! code (`server::start`) with the fake board behind it: what a page gets
//! without the token, from another origin, and with everything right.

use super::super::access::Access;
use super::super::relay::{Ends, Opener, Relay};
use super::super::server::{start, Limits};
use super::super::site::{Page, Site};
use polyturn_bench::fakeboard::FakeDevice;
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::AtomicUsize;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tungstenite::http::Request as HttpRequest;
use tungstenite::Message;

const TOKEN: &str = "00112233445566778899aabbccddeeff";
const LIMITS: Limits = Limits { connections: 4, head: Duration::from_secs(2), reply: Duration::from_secs(2) };

struct Board(Arc<Mutex<FakeDevice>>);

impl Read for Board {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().read(buf)
    }
}

impl Write for Board {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A site with the fake board relayed, `token` asked if given; and the
/// board, to see what reached it.
fn site(token: Option<&str>, relayed: bool) -> (Arc<Site>, Arc<Mutex<FakeDevice>>) {
    let board = Arc::new(Mutex::new(FakeDevice::new()));
    let b = Arc::clone(&board);
    let open: Opener = Box::new(move || -> Result<Ends, String> {
        Ok((Box::new(Board(Arc::clone(&b))), Box::new(Board(Arc::clone(&b)))))
    });
    let mut site = Site::new(Page::Carried(&[("index.html", b"<html>")]), None);
    site.access = Access { token: token.map(String::from) };
    site.relay = relayed.then(|| Relay::start("/dev/ttyACM0", open).unwrap());
    (Arc::new(site), board)
}

/// A listener whose next connection `start` serves, as the accept loop would.
fn serve_one(site: &Arc<Site>) -> (std::net::SocketAddr, std::thread::JoinHandle<()>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    let site = Arc::clone(site);
    let t = std::thread::spawn(move || {
        let open = Arc::new(AtomicUsize::new(0));
        let _ = start(listener.accept().unwrap().0, &site, LIMITS, &open);
    });
    (addr, t)
}

/// A raw request's whole answer.
fn raw(site: &Arc<Site>, head: &str) -> String {
    let (addr, t) = serve_one(site);
    let mut c = TcpStream::connect(addr).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    c.write_all(head.replace("ADDR", &addr.to_string()).as_bytes()).unwrap();
    let mut reply = String::new();
    let _ = c.read_to_string(&mut reply);
    t.join().unwrap();
    reply
}

const UPGRADE: &str = "GET /relay HTTP/1.1\r\nHost: ADDR\r\nOrigin: http://ADDR\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";

#[test]
fn without_the_token_or_with_a_wrong_one_a_page_gets_a_401_and_nothing_of_the_console() {
    let (site, board) = site(Some(TOKEN), true);
    for extra in ["", "Cookie: polyturn-token=00112233445566778899aabbccddeefe\r\n", "Authorization: Bearer x\r\n"] {
        let reply = raw(&site, &format!("{UPGRADE}{extra}\r\n"));
        assert!(reply.starts_with("HTTP/1.1 401 Unauthorized\r\n"), "{extra}: {reply}");
        assert!(reply.contains("WWW-Authenticate: Bearer realm=\"polyturn web\"\r\n"), "{reply}");
        assert!(!reply.contains("ok ") && !reply.contains("hello"), "{reply}");
        // the page itself is refused alike
        let page = raw(&site, &format!("GET / HTTP/1.1\r\nHost: ADDR\r\n{extra}\r\n"));
        assert!(page.starts_with("HTTP/1.1 401 Unauthorized\r\n") && !page.contains("<html>"), "{page}");
    }
    assert!(board.lock().unwrap().received.is_empty());
    // the address's token lets the page in and sets the cookie
    let page = raw(&site, &format!("GET /?token={TOKEN} HTTP/1.1\r\nHost: ADDR\r\n\r\n"));
    assert!(page.starts_with("HTTP/1.1 200 OK\r\n") && page.ends_with("<html>"), "{page}");
    assert!(
        page.contains(&format!("\r\nSet-Cookie: polyturn-token={TOKEN}; Path=/; HttpOnly; SameSite=Strict\r\n")),
        "{page}"
    );
    assert!(page.contains("\r\nX-Polyturn-Board: relay\r\n"), "{page}");
}

#[test]
fn another_origin_is_forbidden_and_a_plain_get_or_no_board_is_refused() {
    let (site, _) = site(None, true);
    let cross = raw(&site, &format!("{}\r\n", UPGRADE.replace("Origin: http://ADDR", "Origin: https://example.com")));
    assert!(cross.starts_with("HTTP/1.1 403 Forbidden\r\n"), "{cross}");
    let plain = raw(&site, "GET /relay HTTP/1.1\r\nHost: ADDR\r\n\r\n");
    assert!(plain.starts_with("HTTP/1.1 400 Bad Request\r\n"), "{plain}");
    let (bare, _) = self::site(None, false);
    assert!(raw(&bare, &format!("{UPGRADE}\r\n")).starts_with("HTTP/1.1 404 Not Found\r\n"));
    assert!(!raw(&bare, "GET / HTTP/1.1\r\n\r\n").contains("X-Polyturn-Board"));
}

/// The page's side: a WebSocket client, with `cookie`.
fn connect(addr: std::net::SocketAddr, cookie: &str) -> tungstenite::WebSocket<TcpStream> {
    let stream = TcpStream::connect(addr).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let req = HttpRequest::builder()
        .uri(format!("ws://{addr}/relay"))
        .header("Host", addr.to_string())
        .header("Origin", format!("http://{addr}"))
        .header("Cookie", cookie)
        .header("Connection", "Upgrade")
        .header("Upgrade", "websocket")
        .header("Sec-WebSocket-Version", "13")
        .header("Sec-WebSocket-Key", tungstenite::handshake::client::generate_key())
        .body(())
        .unwrap();
    tungstenite::client(req, stream).expect("the handshake").0
}

fn next_json(ws: &mut tungstenite::WebSocket<TcpStream>) -> serde_json::Value {
    loop {
        if let Message::Text(t) = ws.read().expect("a message within 5 s") {
            return serde_json::from_str(t.as_str()).unwrap();
        }
    }
}

#[test]
fn with_the_token_a_page_has_the_console_and_dfu_is_refused() {
    let (site, board) = site(Some(TOKEN), true);
    let (addr, t) = serve_one(&site);
    let mut ws = connect(addr, &format!("polyturn-token={TOKEN}"));
    let hello = next_json(&mut ws);
    assert_eq!((hello["t"].as_str(), hello["port"].as_str()), (Some("hello"), Some("/dev/ttyACM0")), "{hello}");
    assert_eq!(next_json(&mut ws), serde_json::json!({"t": "control", "yours": true, "free": false}));
    ws.send(Message::text(r##"{"t":"line","line":"#21 get cpr"}"##)).unwrap();
    assert_eq!(next_json(&mut ws), serde_json::json!({"t": "line", "line": "#21 ok cpr=2400"}));
    ws.send(Message::text(r##"{"t":"line","line":"#22 dfu"}"##)).unwrap();
    let refused = next_json(&mut ws);
    assert!(refused["line"].as_str().unwrap().starts_with("#22 error: relay: dfu is not relayed"), "{refused}");
    ws.send(Message::text("not json")).unwrap();
    assert_eq!(next_json(&mut ws)["t"], "notice");
    ws.close(None).unwrap();
    while ws.read().is_ok() {}
    t.join().unwrap();
    assert_eq!(board.lock().unwrap().received, vec!["#21 get cpr".to_string()]);
}
