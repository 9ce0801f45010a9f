//! The request head: read whole within one deadline and one size bound,
//! its first line parsed and its header fields kept (the relay's upgrade
//! and the token read them; a static file needs none).

use std::io::{ErrorKind, Read};

/// The longest request head taken (the page's are a few hundred bytes).
pub const HEAD_MAX: usize = 16 * 1024;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    Get,
    Head,
}

#[derive(Debug, PartialEq)]
pub struct Request {
    pub method: Method,
    /// The origin-form target as sent (`/path?query`).
    pub target: String,
    /// The header fields, names in lower case, values trimmed (RFC 9110
    /// §5.1: names are case-insensitive; §5.5: surrounding whitespace is
    /// not part of the value). Bounded by `HEAD_MAX`.
    pub headers: Vec<(String, String)>,
}

impl Request {
    /// The first field named `name` (lower case), if any.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }

    /// The value of `key` in the target's query (`?a=1&key=v`), as sent.
    pub fn query(&self, key: &str) -> Option<&str> {
        let query = self.target.split_once('?')?.1.split('#').next()?;
        query.split('&').find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
    }
}

/// Why a connection gets no request: the status line to answer with, or
/// None when the client went away (nobody to answer).
pub type Refusal = Option<&'static str>;

pub const BAD_REQUEST: &str = "400 Bad Request";
pub const NOT_ALLOWED: &str = "405 Method Not Allowed";
pub const TIMEOUT: &str = "408 Request Timeout";
pub const TOO_LARGE: &str = "431 Request Header Fields Too Large";

/// Reads the head (up to its empty line) from `from`, whose reads fail
/// with TimedOut once the request's deadline has passed.
pub fn read(from: &mut impl Read) -> Result<Request, Refusal> {
    let mut head = Vec::with_capacity(1024);
    let mut buf = [0u8; 1024];
    loop {
        let room = (HEAD_MAX - head.len()).min(buf.len());
        if room == 0 {
            return Err(Some(TOO_LARGE));
        }
        let n = match from.read(&mut buf[..room]) {
            Ok(0) => return Err(None),
            Ok(n) => n,
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => return Err(Some(TIMEOUT)),
            Err(_) => return Err(None),
        };
        // only the new bytes (and the two before them) are searched again
        let seen = head.len().saturating_sub(2);
        head.extend_from_slice(&buf[..n]);
        if let Some(end) = head_end(&head, seen) {
            return parse(&head[..end]);
        }
    }
}

/// Where the head's empty line starts. Lines end in CRLF, or in a bare LF,
/// which RFC 9112 §2.2 lets a server accept; both are.
fn head_end(head: &[u8], from: usize) -> Option<usize> {
    let tail = head.get(from..).unwrap_or_default();
    tail.windows(2).enumerate().map(|(i, w)| (from + i, w)).find_map(|(i, w)| match w {
        b"\n\n" => Some(i + 1),
        b"\n\r" if head.get(i + 2) == Some(&b'\n') => Some(i + 1),
        _ => None,
    })
}

/// The request line: `METHOD SP /target SP HTTP/1.x`, nothing looser;
/// then the header fields.
fn parse(head: &[u8]) -> Result<Request, Refusal> {
    let mut lines = head.split(|&b| b == b'\n').map(|l| l.strip_suffix(b"\r").unwrap_or(l));
    let line = lines.next().unwrap_or_default();
    let line = std::str::from_utf8(line).ok().filter(|l| l.is_ascii()).ok_or(Some(BAD_REQUEST))?;
    let parts: Vec<&str> = line.split(' ').collect();
    let [method, target, version] = parts[..] else { return Err(Some(BAD_REQUEST)) };
    if !matches!(version, "HTTP/1.0" | "HTTP/1.1") || method.is_empty() || !target.starts_with('/') {
        return Err(Some(BAD_REQUEST));
    }
    let method = match method {
        "GET" => Method::Get,
        "HEAD" => Method::Head,
        _ => return Err(Some(NOT_ALLOWED)),
    };
    let headers = lines.filter(|l| !l.is_empty()).map(field).collect::<Result<_, _>>()?;
    Ok(Request { method, target: target.to_string(), headers })
}

/// One `name: value` line: a name of token characters (RFC 9110 §5.1),
/// the value text without control characters; anything else is a bad
/// request (a stray CR or a folded line included, RFC 9112 §5.2).
fn field(line: &[u8]) -> Result<(String, String), Refusal> {
    let text = std::str::from_utf8(line).map_err(|_| Some(BAD_REQUEST))?;
    let (name, value) = text.split_once(':').ok_or(Some(BAD_REQUEST))?;
    let token = |c: char| c.is_ascii_alphanumeric() || "!#$%&'*+-.^_`|~".contains(c);
    if name.is_empty() || !name.chars().all(token) || value.chars().any(|c| c.is_control() && c != '\t') {
        return Err(Some(BAD_REQUEST));
    }
    Ok((name.to_ascii_lowercase(), value.trim_matches([' ', '\t']).to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(bytes: &[u8]) -> Result<Request, Refusal> {
        read(&mut &bytes[..])
    }

    #[test]
    fn a_head_ends_at_its_empty_line_with_or_without_carriage_returns() {
        let host = vec![("host".to_string(), "x".to_string())];
        let get = |t: &str| Ok(Request { method: Method::Get, target: t.to_string(), headers: host.clone() });
        assert_eq!(read_all(b"GET /a HTTP/1.1\r\nHost: x\r\n\r\n"), get("/a"));
        assert_eq!(read_all(b"GET /b HTTP/1.1\nHost: x\n\n"), get("/b"));
        assert_eq!(read_all(b"GET /c HTTP/1.0\r\nHost: x\n\r\nbody"), get("/c"));
        // the client closed before its empty line: nobody to answer
        assert_eq!(read_all(b"GET / HTTP/1.1\r\n"), Err(None));
    }

    #[test]
    fn a_loose_request_line_is_a_bad_request_and_another_method_not_allowed() {
        for bad in
            ["GET /\r\n\r\n", "GET  / HTTP/1.1\r\n\r\n", "GET / HTTP/2\r\n\r\n", "GET x HTTP/1.1\r\n\r\n", "\r\n\r\n"]
        {
            assert_eq!(read_all(bad.as_bytes()), Err(Some(BAD_REQUEST)), "{bad:?}");
        }
        assert_eq!(read_all(b"GET /\xc3\xa9 HTTP/1.1\r\n\r\n"), Err(Some(BAD_REQUEST)));
        assert_eq!(read_all(b"DELETE / HTTP/1.1\r\n\r\n"), Err(Some(NOT_ALLOWED)));
        let head = read_all(b"HEAD /x HTTP/1.1\r\n\r\n").unwrap();
        assert_eq!(head.method, Method::Head);
    }

    #[test]
    fn header_fields_are_kept_by_lower_case_name_and_a_broken_one_is_a_bad_request() {
        let r =
            read_all(b"GET /?a=1&token=ab%20c HTTP/1.1\r\nHOST:  127.0.0.1:80 \r\nUpgrade: websocket\r\n\r\n").unwrap();
        assert_eq!(r.header("host"), Some("127.0.0.1:80"));
        assert_eq!(r.header("upgrade"), Some("websocket"));
        assert_eq!(r.header("origin"), None);
        assert_eq!((r.query("token"), r.query("a"), r.query("tok")), (Some("ab%20c"), Some("1"), None));
        for bad in [
            "GET / HTTP/1.1\r\nno colon\r\n\r\n",
            "GET / HTTP/1.1\r\n folded: x\r\n\r\n",
            "GET / HTTP/1.1\r\nA: b\rc\r\n\r\n",
        ] {
            assert_eq!(read_all(bad.as_bytes()), Err(Some(BAD_REQUEST)), "{bad:?}");
        }
    }

    #[test]
    fn a_head_past_the_bound_is_refused_not_kept() {
        let mut big = b"GET / HTTP/1.1\r\nX: ".to_vec();
        big.resize(HEAD_MAX + 10, b'a');
        assert_eq!(read_all(&big), Err(Some(TOO_LARGE)));
    }
}
