//! One page's WebSocket to the relay (`/relay`): the opening handshake of
//! RFC 6455 §4.2 answered from the request head the server already read,
//! then tungstenite's framing. The page sends `{"t":"line","line":"#5
//! status"}` or `{"t":"take"}`; it hears the relay's events as JSON
//! (`relay::Event`). Every wait is bounded: the socket is polled, a page
//! silent for `SILENT_MAX` (no pong to the pings) is let go, and a write
//! that stalls for `WRITE_WAIT` ends the connection.

use super::relay::{Event, Member, Relay};
use super::request::{Request, BAD_REQUEST};
use serde::Deserialize;
use std::io::{self, Write};
use std::net::TcpStream;
use std::sync::mpsc::TryRecvError;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tungstenite::protocol::{Role, WebSocketConfig};
use tungstenite::{Message, WebSocket};

/// How often the socket is looked at for the page's messages.
const POLL: Duration = Duration::from_millis(20);
const PING_EVERY: Duration = Duration::from_secs(10);
const SILENT_MAX: Duration = Duration::from_secs(30);
const WRITE_WAIT: Duration = Duration::from_secs(5);
/// A page's message is one console line in JSON: far less than this.
const MESSAGE_MAX: usize = 4096;

/// What a page may send.
#[derive(Debug, Deserialize)]
#[serde(tag = "t", rename_all = "lowercase")]
enum FromPage {
    Line { line: String },
    Take,
}

/// The `Sec-WebSocket-Accept` for a request that asks for a WebSocket
/// (RFC 6455 §4.2.1: GET, `Upgrade: websocket`, `Connection` naming
/// `upgrade`, version 13, a key); Err is the status line of a refusal.
pub fn accept_key(r: &Request) -> Result<String, &'static str> {
    let has = |name: &str, word: &str| {
        r.header(name).is_some_and(|v| v.split(',').any(|w| w.trim().eq_ignore_ascii_case(word)))
    };
    if !has("upgrade", "websocket") || !has("connection", "upgrade") || r.header("sec-websocket-version") != Some("13")
    {
        return Err(BAD_REQUEST);
    }
    let key = r.header("sec-websocket-key").filter(|k| k.len() == 24).ok_or(BAD_REQUEST)?;
    Ok(tungstenite::handshake::derive_accept_key(key.as_bytes()))
}

/// Answers the handshake, then serves the page until it, or the board,
/// goes.
pub fn serve(mut stream: TcpStream, accept: &str, relay: &Arc<Relay>) {
    let _ = stream.set_write_timeout(Some(WRITE_WAIT));
    let head = format!(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Accept: {accept}\r\n\r\n"
    );
    if stream.write_all(head.as_bytes()).is_err() || stream.set_read_timeout(Some(POLL)).is_err() {
        return;
    }
    let config = WebSocketConfig::default().max_message_size(Some(MESSAGE_MAX)).max_frame_size(Some(MESSAGE_MAX));
    let mut ws = WebSocket::from_raw_socket(stream, Role::Server, Some(config));
    match relay.join() {
        Ok(member) => {
            let _ = talk(&mut ws, relay, &member);
            relay.leave(member.id);
        }
        Err(why) => {
            let _ = send(&mut ws, &Event::Gone { why });
        }
    }
    let _ = ws.close(None);
    let _ = ws.flush();
}

/// The page's messages to the relay and the relay's events to the page,
/// until either side ends (Err: the socket failed).
fn talk(ws: &mut WebSocket<TcpStream>, relay: &Relay, member: &Member) -> tungstenite::Result<()> {
    let (mut heard, mut pinged) = (Instant::now(), Instant::now());
    loop {
        match ws.read() {
            Ok(Message::Text(text)) => {
                heard = Instant::now();
                if let Some(answer) = answer(relay, member.id, text.as_str()) {
                    send(ws, &answer)?;
                }
            }
            Ok(Message::Close(_)) => return Ok(()),
            Ok(_) => heard = Instant::now(),
            Err(tungstenite::Error::Io(e))
                if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {}
            Err(e) => return Err(e),
        }
        loop {
            match member.events.try_recv() {
                Ok(event) => {
                    send(ws, &event)?;
                    if matches!(event, Event::Gone { .. }) {
                        return Ok(());
                    }
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    let why = "this page fell behind the board's lines and was let go: reconnect".to_string();
                    return send(ws, &Event::Gone { why });
                }
            }
        }
        if heard.elapsed() > SILENT_MAX {
            return Ok(());
        }
        if pinged.elapsed() > PING_EVERY {
            ws.send(Message::Ping(Vec::new().into()))?;
            pinged = Instant::now();
        }
    }
}

/// What the page's message gets back, if anything: a refused line's
/// reply, or a notice.
fn answer(relay: &Relay, id: u64, text: &str) -> Option<Event> {
    match serde_json::from_str::<FromPage>(text) {
        Ok(FromPage::Line { line }) => relay.send(id, &line).err().map(|line| Event::Line { line }),
        Ok(FromPage::Take) => relay.take(id).err().map(|why| Event::Notice { why }),
        Err(_) => {
            Some(Event::Notice { why: "the relay takes {\"t\":\"line\",\"line\":...} or {\"t\":\"take\"}".into() })
        }
    }
}

fn send(ws: &mut WebSocket<TcpStream>, event: &Event) -> tungstenite::Result<()> {
    let json = serde_json::to_string(event).unwrap_or_default();
    ws.send(Message::text(json))
}

#[cfg(test)]
#[path = "socket_tests.rs"]
mod tests;
