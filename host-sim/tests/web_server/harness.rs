//! The harness of `web_server.rs`: a page folder, the server as a child
//! process on a free port, raw requests with deadlines, replies parsed.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

pub const POLYTURN: &str = env!("CARGO_BIN_EXE_polyturn");
pub const WASM: &[u8] = b"\0asm\x01\0\0\0";
/// The longest a test waits for one reply from a healthy server.
pub const REPLY_WAIT: Duration = Duration::from_secs(5);

/// A page folder in the temp directory, removed when dropped.
pub struct Page(pub PathBuf);

impl Page {
    pub fn new(name: &str) -> Page {
        let d = std::env::temp_dir().join(format!("polyturn-web-server-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("pkg")).unwrap();
        std::fs::write(d.join("index.html"), "<p>page</p>").unwrap();
        std::fs::write(d.join("pkg/polyturn_web_bg.wasm"), WASM).unwrap();
        std::fs::write(d.join("pkg/polyturn_web.js"), "export {};").unwrap();
        std::fs::write(d.join("style.css"), "p {}").unwrap();
        std::fs::write(d.join("icon.svg"), "<svg/>").unwrap();
        Page(d)
    }
}

impl Drop for Page {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `polyturn web --port 0 --no-open --dir DIR`, killed when dropped.
pub struct Server {
    child: Child,
    port: u16,
}

impl Server {
    pub fn start(dir: &Path) -> Server {
        let mut child = Command::new(POLYTURN)
            .args(["web", "--port", "0", "--no-open", "--dir"])
            .arg(dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut line = String::new();
            let _ = BufReader::new(stdout).read_line(&mut line);
            let _ = tx.send(line);
        });
        let line = rx.recv_timeout(Duration::from_secs(10)).unwrap_or_default();
        let after = line.split("http://127.0.0.1:").nth(1).unwrap_or("");
        let port = after.split('/').next().and_then(|p| p.parse().ok());
        let Some(port) = port else {
            let _ = child.kill();
            let _ = child.wait();
            panic!("polyturn web printed no address: {line:?}");
        };
        Server { child, port }
    }

    pub fn connect(&self) -> TcpStream {
        let s = TcpStream::connect_timeout(&([127, 0, 0, 1], self.port).into(), REPLY_WAIT).unwrap();
        s.set_read_timeout(Some(REPLY_WAIT)).unwrap();
        s.set_write_timeout(Some(REPLY_WAIT)).unwrap();
        s
    }

    /// Sends `raw` and reads the reply until the server closes, at most
    /// REPLY_WAIT in all and 1 MiB; a partial reply is returned as it is.
    pub fn ask(&self, raw: &[u8]) -> Vec<u8> {
        let mut s = self.connect();
        let _ = s.write_all(raw);
        read_reply(&mut s, REPLY_WAIT)
    }

    pub fn get(&self, path: &str) -> Reply {
        Reply::parse(&self.ask(format!("GET {path} HTTP/1.1\r\nHost: x\r\n\r\n").as_bytes()))
    }

    /// The server's threads, from /proc (Linux).
    pub fn threads(&self) -> usize {
        std::fs::read_dir(format!("/proc/{}/task", self.child.id())).map_or(0, |d| d.count())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

pub fn read_reply(s: &mut TcpStream, wait: Duration) -> Vec<u8> {
    let end = Instant::now() + wait;
    let mut out = Vec::new();
    let mut buf = [0u8; 8192];
    while out.len() < 1 << 20 {
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() || s.set_read_timeout(Some(left)).is_err() {
            break;
        }
        match s.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => out.extend_from_slice(&buf[..n]),
        }
    }
    out
}

/// A reply taken apart: status code, header lines, body.
pub struct Reply {
    pub status: u16,
    pub head: String,
    pub body: Vec<u8>,
}

impl Reply {
    pub fn parse(raw: &[u8]) -> Reply {
        let split = raw.windows(4).position(|w| w == b"\r\n\r\n");
        let (head, body) = split.map_or((raw, &[][..]), |i| (&raw[..i], &raw[i + 4..]));
        let head = String::from_utf8_lossy(head).into_owned();
        let status = head.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
        Reply { status, head, body: body.to_vec() }
    }

    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body[..self.body.len().min(200)]).into_owned()
    }

    pub fn header(&self, name: &str) -> Option<&str> {
        let prefix = format!("{}:", name.to_ascii_lowercase());
        self.head.lines().find(|l| l.to_ascii_lowercase().starts_with(&prefix)).map(|l| l[prefix.len()..].trim())
    }
}

/// Shows the head and the body's start, not a whole file as numbers.
impl std::fmt::Debug for Reply {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{:?} + {} body bytes {:?}", self.head, self.body.len(), self.text())
    }
}

/// Runs `polyturn web --no-open --port 0 --dir DIR`, which must refuse at
/// once: its exit status and stderr.
pub fn refused(dir: &Path) -> (Option<i32>, String) {
    let mut child = Command::new(POLYTURN)
        .args(["web", "--no-open", "--port", "0", "--dir"])
        .arg(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let end = Instant::now() + Duration::from_secs(10);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > end {
            let _ = child.kill();
            let _ = child.wait();
            panic!("polyturn web served {} instead of refusing it", dir.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut err = String::new();
    let _ = child.stderr.take().unwrap().read_to_string(&mut err);
    (child.wait().unwrap().code(), err)
}
