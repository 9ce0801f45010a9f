//! Who may have the page and the board's console. On loopback (the
//! default) every request from this machine is served; `--listen ADDR`
//! (to serve beyond it) asks every request for the token printed at start:
//! in the address (`?token=`), then in the cookie set from it, or as
//! `Authorization: Bearer`. Without it, a 401 and nothing else.
//!
//! The relay's upgrade is also held to its own origin: a WebSocket is not
//! bound by the browser's same-origin policy (RFC 6455 §10.2: the server
//! must check `Origin`), so any site open in the browser could otherwise
//! reach the board on 127.0.0.1; and on loopback the `Host` must name
//! loopback, so a name rebound to 127.0.0.1 by another site's DNS is
//! refused too.

use super::request::Request;

pub const UNAUTHORIZED: &str = "401 Unauthorized";
pub const FORBIDDEN: &str = "403 Forbidden";
/// The cookie the token is kept in once the address gave it.
const COOKIE: &str = "polyturn-token";

#[derive(Debug, Clone, Default)]
pub struct Access {
    /// Asked of every request when listening beyond loopback.
    pub token: Option<String>,
}

/// A request let in; `set_cookie` when its address carried the token,
/// so the page's later requests (scripts, the WebSocket) carry it too.
#[derive(Debug, PartialEq)]
pub struct Granted {
    pub set_cookie: Option<String>,
}

impl Access {
    /// Lets `r` in, or the status line of the refusal.
    pub fn check(&self, r: &Request) -> Result<Granted, &'static str> {
        let Some(token) = &self.token else { return Ok(Granted { set_cookie: None }) };
        if r.query("token").is_some_and(|t| same(t, token)) {
            let cookie = format!("Set-Cookie: {COOKIE}={token}; Path=/; HttpOnly; SameSite=Strict\r\n");
            return Ok(Granted { set_cookie: Some(cookie) });
        }
        let from_cookie =
            r.header("cookie").into_iter().flat_map(|c| c.split(';')).any(|kv| {
                kv.trim().strip_prefix(COOKIE).and_then(|v| v.strip_prefix('=')).is_some_and(|v| same(v, token))
            });
        let bearer = r.header("authorization").and_then(|a| a.strip_prefix("Bearer ")).is_some_and(|t| same(t, token));
        if from_cookie || bearer {
            return Ok(Granted { set_cookie: None });
        }
        Err(UNAUTHORIZED)
    }

    /// The relay's upgrade: `Origin`, when a browser sends one, must be
    /// this server as the request names it; on loopback the `Host` must be
    /// a loopback name.
    pub fn check_relay(&self, r: &Request) -> Result<(), &'static str> {
        let host = r.header("host").ok_or(FORBIDDEN)?;
        if self.token.is_none() && !is_loopback_host(host) {
            return Err(FORBIDDEN);
        }
        match r.header("origin") {
            Some(origin) if origin != format!("http://{host}") => Err(FORBIDDEN),
            _ => Ok(()),
        }
    }
}

/// `127.x.x.x`, `localhost` or `[::1]`, with or without a port.
fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        Some(v6) => v6.split(']').next().unwrap_or_default(),
        None => host.rsplit_once(':').map_or(host, |(n, _)| n),
    };
    name.eq_ignore_ascii_case("localhost") || name.parse::<std::net::IpAddr>().is_ok_and(|ip| ip.is_loopback())
}

/// Equal, in a time that does not depend on where they first differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// A new token: 128 bits from the system's generator, as hex.
pub fn new_token() -> Result<String, String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| format!("no random token: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

#[cfg(test)]
mod tests {
    use super::super::request::Method;
    use super::*;

    fn req(target: &str, headers: &[(&str, &str)]) -> Request {
        let headers = headers.iter().map(|(n, v)| (n.to_string(), v.to_string())).collect();
        Request { method: Method::Get, target: target.into(), headers }
    }

    const TOKEN: &str = "0123456789abcdef0123456789abcdef";

    #[test]
    fn on_loopback_everything_is_let_in_without_a_token() {
        assert_eq!(Access::default().check(&req("/", &[])), Ok(Granted { set_cookie: None }));
    }

    #[test]
    fn beyond_loopback_a_missing_or_wrong_token_is_a_401() {
        let a = Access { token: Some(TOKEN.into()) };
        for r in [
            req("/", &[]),
            req("/?token=", &[]),
            req("/?token=0123456789abcdef0123456789abcdee", &[]),
            req(&format!("/?token={TOKEN}x"), &[]),
            req("/js/main.js", &[("cookie", "polyturn-token=nope")]),
            req("/js/main.js", &[("cookie", &format!("other-token={TOKEN}"))]),
            req("/relay", &[("authorization", "Bearer 0")]),
            req("/relay", &[("authorization", TOKEN)]),
        ] {
            assert_eq!(a.check(&r), Err(UNAUTHORIZED), "{r:?}");
        }
    }

    #[test]
    fn the_token_in_the_address_sets_the_cookie_the_later_requests_carry() {
        let a = Access { token: Some(TOKEN.into()) };
        let first = a.check(&req(&format!("/?v=1&token={TOKEN}"), &[])).unwrap();
        let cookie = first.set_cookie.unwrap();
        assert!(cookie.starts_with(&format!("Set-Cookie: polyturn-token={TOKEN};")), "{cookie}");
        assert!(cookie.contains("HttpOnly") && cookie.contains("SameSite=Strict"), "{cookie}");
        let later = req("/pkg/x.wasm", &[("cookie", &format!("a=b; polyturn-token={TOKEN}"))]);
        assert_eq!(a.check(&later), Ok(Granted { set_cookie: None }));
        let bearer = req("/relay", &[("authorization", &format!("Bearer {TOKEN}"))]);
        assert_eq!(a.check(&bearer), Ok(Granted { set_cookie: None }));
    }

    #[test]
    fn the_relay_is_refused_to_another_origin_and_on_loopback_to_another_host() {
        let open = Access::default();
        let ok = |h: &str, o: &str| open.check_relay(&req("/relay", &[("host", h), ("origin", o)]));
        assert_eq!(ok("127.0.0.1:8177", "http://127.0.0.1:8177"), Ok(()));
        assert_eq!(ok("localhost:8177", "http://localhost:8177"), Ok(()));
        assert_eq!(ok("[::1]:8177", "http://[::1]:8177"), Ok(()));
        // another site open in the same browser
        assert_eq!(ok("127.0.0.1:8177", "https://example.com"), Err(FORBIDDEN));
        // a name another site's DNS pointed at 127.0.0.1
        assert_eq!(ok("rebound.example:8177", "http://rebound.example:8177"), Err(FORBIDDEN));
        assert_eq!(open.check_relay(&req("/relay", &[])), Err(FORBIDDEN), "no Host");
        // a program without Origin (not a browser) on loopback
        assert_eq!(open.check_relay(&req("/relay", &[("host", "127.0.0.1:1")])), Ok(()));
        let shop = Access { token: Some(TOKEN.into()) };
        let lan = req("/relay", &[("host", "192.0.2.7:8177"), ("origin", "http://192.0.2.7:8177")]);
        assert_eq!(shop.check_relay(&lan), Ok(()));
        let cross = req("/relay", &[("host", "192.0.2.7:8177"), ("origin", "http://192.0.2.8:8177")]);
        assert_eq!(shop.check_relay(&cross), Err(FORBIDDEN));
    }

    #[test]
    fn tokens_are_32_hex_digits_and_differ() {
        let (a, b) = (new_token().unwrap(), new_token().unwrap());
        assert!(a.len() == 32 && a.chars().all(|c| c.is_ascii_hexdigit()), "{a}");
        assert_ne!(a, b);
    }
}
