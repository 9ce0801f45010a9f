//! The USB scenario: boot, plug the emulated host in, enumerate; then the console
//! line `status` on the bulk OUT endpoint, its reply read from bulk IN until its
//! CRLF (firmware/src/app/usb.rs `send`: the reply then "\r\n"); then `set cpr 0`,
//! whose reply must be the console's error. Each prints its reply with the wall
//! and emulated time; enumeration plus one status round trip should take under
//! 5 s of wall time.

use super::host::Host;
use crate::checks::{faults, Report};
use crate::image::Image;
use crate::machine::Machine;
use std::rc::Rc;
use std::time::Instant;

const MS: u64 = crate::MS;
/// Emulated time allowed to enumerate (from boot) and for one reply.
const ENUM_LIMIT_MS: u64 = 2_000;
const REPLY_LIMIT_MS: u64 = 1_000;
const WALL_TARGET_S: f64 = 5.0;

pub fn host(m: &mut Machine) -> &mut Host {
    m.chip().host.get_or_insert_with(Box::default)
}

fn stopped(m: &mut Machine) -> bool {
    host(m).error().is_some() || !m.chip().faults.is_empty()
}

/// Boots and enumerates; the machine, emulated ms and wall s of enumeration.
pub fn enumerate(image: &Rc<Image>) -> Result<(Machine, f64, f64), String> {
    let m = crate::boot(image)?;
    enumerate_on(m)
}

/// Plugs the host into a booted machine and enumerates.
pub fn enumerate_on(m: Machine) -> Result<(Machine, f64, f64), String> {
    let (m, r) = enumerate_keeping(m);
    r.map(|(at, wall)| (m, at, wall))
}

/// The same, giving the machine back whatever happened (to see why it stopped).
pub fn enumerate_keeping(mut m: Machine) -> (Machine, Result<(f64, f64), String>) {
    let wall = Instant::now();
    host(&mut m);
    while !host(&mut m).configured() && !stopped(&mut m) && m.chip().now < ENUM_LIMIT_MS * MS {
        m.run(MS);
    }
    let at = host(&mut m).configured_at.unwrap_or(m.chip().now);
    let problem = host(&mut m).error().map(str::to_string).or_else(|| {
        let f = faults(&mut m);
        (f != "none").then_some(f)
    });
    let r = match (host(&mut m).configured(), problem) {
        (true, None) => Ok((at as f64 / MS as f64, wall.elapsed().as_secs_f64())),
        (_, Some(p)) => Err(p),
        _ => Err(format!("the device never enumerated within {ENUM_LIMIT_MS} ms")),
    };
    (m, r)
}

/// Sends `line`, reads until a CRLF; the reply (without it), emulated ms, wall s.
pub fn exchange(m: &mut Machine, line: &str) -> Result<(String, f64, f64), String> {
    exchange_within(m, line, REPLY_LIMIT_MS)
}

/// The same, allowing `limit_ms` of emulated time for the reply.
pub fn exchange_within(m: &mut Machine, line: &str, limit_ms: u64) -> Result<(String, f64, f64), String> {
    let (wall, t0) = (Instant::now(), m.chip().now);
    if !host(m).send(line.as_bytes()) {
        return Err("the host's OUT buffer is full".into());
    }
    let mut got = Vec::new();
    while !got.ends_with(b"\r\n") && !stopped(m) && m.chip().now - t0 < limit_ms * MS {
        m.run(MS / 10);
        got.extend(host(m).received());
    }
    if let Some(e) = host(m).error().map(str::to_string) {
        return Err(e);
    }
    if !got.ends_with(b"\r\n") {
        let f = faults(m);
        return Err(format!("no complete reply within {limit_ms} ms (got {got:?}; faults: {f})"));
    }
    let text = String::from_utf8_lossy(&got[..got.len() - 2]).into_owned();
    Ok((text, (m.chip().now - t0) as f64 / MS as f64, wall.elapsed().as_secs_f64()))
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let (mut m, en_ms, en_wall) = match enumerate(image) {
        Ok(e) => e,
        Err(e) => {
            r.line(false, "usb-enumerate", &e);
            return Ok(0);
        }
    };
    let h = host(&mut m);
    let what = format!("{:04x}:{:04x} {:?}", super::descriptors::VID, super::descriptors::PID, h.strings);
    let attach = h.attached_at.unwrap_or(0) as f64 / MS as f64;
    let irqs = m.chip().entries.get(&(16 + crate::svd::irq("OTG_FS"))).copied().unwrap_or(0);
    let text = format!(
        "{what}; pulled up at {attach:.1} ms, configured at {en_ms:.1} ms emulated after {irqs} OTG_FS interrupts, {en_wall:.2} s wall"
    );
    r.line(true, "usb-enumerate", &text);
    let status = exchange(&mut m, "status\n");
    let ok = matches!(&status, Ok((s, _, _)) if !s.is_empty() && !s.starts_with("error"));
    r.line(ok, "usb-status", &said(&status));
    if let Ok((_, _, w)) = status {
        let total = en_wall + w;
        r.line(
            total < WALL_TARGET_S,
            "usb-wall",
            &format!("enumeration + status {total:.2} s wall (under {WALL_TARGET_S} s)"),
        );
    }
    let cpr = exchange(&mut m, "set cpr 0\n");
    let ok = matches!(&cpr, Ok((s, _, _)) if s.starts_with("error"));
    r.line(ok, "usb-set-cpr-0", &said(&cpr));
    Ok(m.chip().now)
}

fn said(x: &Result<(String, f64, f64), String>) -> String {
    match x {
        Ok((s, ms, w)) => format!("reply {s:?} after {ms:.2} ms emulated, {w:.3} s wall"),
        Err(e) => e.clone(),
    }
}
