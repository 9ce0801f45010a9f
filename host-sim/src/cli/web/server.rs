//! The accept loop and one connection's life: at most `connections` at
//! once, each on its own thread (a 503 past that, answered by the accept
//! loop itself), one request each (`Connection: close`), with one deadline
//! for the whole head and another for the whole reply. Every request is
//! first let in or refused by the site's `Access` (a 401 beyond
//! loopback without the token); `/relay` becomes the page's WebSocket to
//! the board when one is relayed (`socket.rs`), with no reply deadline.

use super::access::{Granted, UNAUTHORIZED};
use super::files::Body;
use super::files::NOT_FOUND;
use super::request::{self, Method, Request, NOT_ALLOWED};
use super::site::Site;
use super::socket;
use super::timed::Timed;
use std::io::{self, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Connections served at once. Chromium opens six per host; the rest
    /// is room for a second tab and for stragglers being cut off.
    pub connections: usize,
    /// From accept to the head's empty line, however the bytes trickle in.
    pub head: Duration,
    /// From the head to the reply's last byte (a few MB over loopback).
    pub reply: Duration,
}

pub const LIMITS: Limits = Limits { connections: 32, head: Duration::from_secs(10), reply: Duration::from_secs(60) };

const BUSY: &str = "503 Service Unavailable";
/// How long what a client sends after its head is read and dropped.
const LINGER: Duration = Duration::from_millis(500);

pub fn serve(listener: &TcpListener, site: &Arc<Site>, limits: Limits) {
    let open = Arc::new(AtomicUsize::new(0));
    loop {
        match listener.accept() {
            Ok((stream, _)) => {
                if let Err(stream) = start(stream, site, limits, &open) {
                    busy(&stream);
                }
            }
            // out of file descriptors, say: wait for some to close, not spin
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    }
}

/// One of the `max` places for a connection, given back when dropped.
struct Slot(Arc<AtomicUsize>);

impl Slot {
    fn take(open: &Arc<AtomicUsize>, max: usize) -> Option<Slot> {
        let taken = open.fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| (n < max).then_some(n + 1));
        taken.ok().map(|_| Slot(Arc::clone(open)))
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

/// Hands the connection to a new thread; Err gives it back when there is
/// no place or no thread for it. (The stream goes over a channel so that
/// a failed spawn does not take it down unanswered.)
pub(super) fn start(
    stream: TcpStream,
    site: &Arc<Site>,
    limits: Limits,
    open: &Arc<AtomicUsize>,
) -> Result<(), TcpStream> {
    let Some(slot) = Slot::take(open, limits.connections) else { return Err(stream) };
    let accepted = Instant::now();
    let site = Arc::clone(site);
    let (tx, rx) = mpsc::sync_channel::<TcpStream>(1);
    let spawned = std::thread::Builder::new().name("polyturn-web".into()).spawn(move || {
        let _slot = slot;
        if let Ok(stream) = rx.recv() {
            connection(&site, stream, limits, accepted);
        }
    });
    match spawned {
        Ok(_) => tx.send(stream).map_err(|e| e.0),
        Err(_) => Err(stream),
    }
}

/// The 503, from the accept loop: a reply this small fits a fresh
/// socket's buffer, and the write timeout bounds it if it did not.
fn busy(stream: &TcpStream) {
    let _ = stream.set_write_timeout(Some(Duration::from_secs(1)));
    let _ = refuse(&mut &*stream, BUSY, true);
    let _ = stream.shutdown(Shutdown::Write);
}

fn connection(site: &Site, stream: TcpStream, limits: Limits, accepted: Instant) {
    let request = request::read(&mut Timed { stream: &stream, end: accepted + limits.head });
    let out = &mut Timed { stream: &stream, end: Instant::now() + limits.reply };
    let replied = match request {
        Ok(r) => match site.access.check(&r) {
            Ok(_) if is_relay(&r.target) => match relay(site, &r) {
                Ok(accept) => return upgrade(site, stream, &accept),
                Err(status) => refuse(out, status, r.method == Method::Get),
            },
            Ok(granted) => answer(out, site, &r, &granted),
            Err(status) => refuse(out, status, r.method == Method::Get),
        },
        Err(Some(status)) => refuse(out, status, true),
        Err(None) => return,
    };
    // a reply cut short by its deadline is over: nothing to protect
    if replied.is_ok() {
        linger(&stream);
    }
}

fn is_relay(target: &str) -> bool {
    target.split(['?', '#']).next() == Some("/relay")
}

/// The handshake's accept key if `r` may have the relay; Err is the
/// status line of the refusal.
fn relay(site: &Site, r: &Request) -> Result<String, &'static str> {
    if site.relay.is_none() {
        return Err(NOT_FOUND);
    }
    site.access.check_relay(r)?;
    socket::accept_key(r)
}

fn upgrade(site: &Site, stream: TcpStream, accept: &str) {
    if let Some(relay) = &site.relay {
        socket::serve(stream, accept, relay);
    }
}

fn answer(out: &mut impl Write, site: &Site, r: &Request, granted: &Granted) -> io::Result<()> {
    let with_body = r.method == Method::Get;
    match site.find(&r.target) {
        Ok(found) => {
            let extra = format!("{}{}", site.header(), granted.set_cookie.as_deref().unwrap_or_default());
            head(out, "200 OK", found.kind, found.len, &extra)?;
            if with_body {
                match found.body {
                    // streamed, never read whole; Content-Length bytes at most
                    Body::File(file) => {
                        io::copy(&mut file.take(found.len), out)?;
                    }
                    Body::Bytes(bytes) => out.write_all(bytes)?,
                }
            }
            Ok(())
        }
        Err(status) => refuse(out, status, with_body),
    }
}

/// A refusal: its status line, also as a plain-text body unless for HEAD.
fn refuse(out: &mut impl Write, status: &str, with_body: bool) -> io::Result<()> {
    let text = match status {
        UNAUTHORIZED => format!("{status}: open the address polyturn web printed when it started, with its ?token=\n"),
        _ => format!("{status}\n"),
    };
    let extra = match status {
        NOT_ALLOWED => "Allow: GET, HEAD\r\n",
        BUSY => "Retry-After: 1\r\n",
        // RFC 9110 §11.6.1: a 401 names a scheme the server takes
        UNAUTHORIZED => "WWW-Authenticate: Bearer realm=\"polyturn web\"\r\n",
        _ => "",
    };
    head(out, status, "text/plain; charset=utf-8", text.len() as u64, extra)?;
    if with_body {
        out.write_all(text.as_bytes())?;
    }
    Ok(())
}

fn head(out: &mut impl Write, status: &str, kind: &str, len: u64, extra: &str) -> io::Result<()> {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {len}\r\n{extra}\
         Cache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n"
    );
    out.write_all(head.as_bytes())
}

/// Closes the write side, then reads and drops what the client still
/// sends, briefly: a socket closed with unread bytes is reset, and the
/// reset can destroy the reply before the client has read it.
fn linger(stream: &TcpStream) {
    let _ = stream.shutdown(Shutdown::Write);
    let mut rest = Timed { stream, end: Instant::now() + LINGER };
    let _ = io::copy(&mut (&mut rest).take(64 * 1024), &mut io::sink());
}

#[cfg(test)]
#[path = "server_tests.rs"]
mod tests;
