//! What the server answers from: the page, from a folder or carried in
//! the binary, and the firmware image a release `polyturn` carries, at
//! `/firmware/<release file name>` (every reply names it in a header, for
//! the page's Flash view). Either way a target is named by
//! `files::relative`'s rules.

use super::super::carried::{self, Firmware};
use super::access::Access;
use super::files::{self, content_type, Body, Found, NOT_FOUND};
use super::relay::Relay;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub enum Page {
    /// A canonical folder: its files are judged on disk (files::find).
    Folder(PathBuf),
    /// Files compiled in: only these names exist.
    Carried(carried::Page),
}

pub struct Site {
    pub page: Page,
    pub firmware: Option<Firmware>,
    /// Who is let in (a token beyond loopback).
    pub access: Access,
    /// The board's console, when served with one (`--board`).
    pub relay: Option<Arc<Relay>>,
}

impl Site {
    /// The page and image alone, for this machine only (no token, no board).
    pub fn new(page: Page, firmware: Option<Firmware>) -> Site {
        Site { page, firmware, access: Access::default(), relay: None }
    }

    /// What `target` (`/path?query`) names; Err is the refusal's status line.
    pub fn find(&self, target: &str) -> Result<Found, &'static str> {
        let name = name(&files::relative(target)?);
        if let Some(fw) = self.firmware.filter(|fw| fw.url_path() == name) {
            return Ok(bytes(fw.bytes, &name));
        }
        match &self.page {
            Page::Folder(root) => files::find(root, target),
            Page::Carried(files) => files.iter().find(|(n, _)| *n == name).map(|(n, b)| bytes(b, n)).ok_or(NOT_FOUND),
        }
    }

    /// Where the carried image is, for the page's Flash view: a header on
    /// every reply rather than a file to probe, as a 404 from a static
    /// host would be an error in the browser's console.
    /// So too whether the board is relayed (`X-Polyturn-Board`), for the
    /// Device view.
    pub fn header(&self) -> String {
        let firmware = self.firmware.map(|fw| format!("X-Polyturn-Firmware: {}\r\n", fw.url_path()));
        let board = self.relay.as_ref().map(|_| "X-Polyturn-Board: relay\r\n");
        format!("{}{}", firmware.unwrap_or_default(), board.unwrap_or_default())
    }
}

/// A relative path's names joined with '/', as the carried page's are
/// (whatever the host's separator).
fn name(rel: &Path) -> String {
    let parts: Vec<_> = rel.components().map(|c| c.as_os_str().to_string_lossy()).collect();
    parts.join("/")
}

fn bytes(b: &'static [u8], name: &str) -> Found {
    Found { body: Body::Bytes(b), len: b.len() as u64, kind: content_type(Path::new(name)) }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAGE: carried::Page = &[("index.html", b"<html>"), ("pkg/polyturn_web_bg.wasm", b"\0asm")];
    const FW: Firmware = Firmware { name: "polyturn-9.9.9-stm32f411ce.bin", bytes: b"image" };

    fn carried_site() -> Site {
        Site::new(Page::Carried(PAGE), Some(FW))
    }

    fn body(site: &Site, target: &str) -> Result<(&'static [u8], &'static str), &'static str> {
        let found = site.find(target)?;
        match found.body {
            Body::Bytes(b) => Ok((b, found.kind)),
            Body::File(_) => panic!("{target}: a carried file came from disk"),
        }
    }

    #[test]
    fn a_carried_page_answers_its_own_names_only() {
        let site = carried_site();
        assert_eq!(body(&site, "/"), Ok((&b"<html>"[..], "text/html; charset=utf-8")));
        assert_eq!(body(&site, "/pkg/polyturn_web_bg.wasm?v=1"), Ok((&b"\0asm"[..], "application/wasm")));
        assert_eq!(
            body(&site, "/firmware/polyturn-9.9.9-stm32f411ce.bin"),
            Ok((&b"image"[..], "application/octet-stream"))
        );
        for absent in ["/pkg", "/other.js", "/pkg/../index.html", "/.index.html", "/firmware/x.bin", "/index.html/"] {
            assert_eq!(body(&site, absent).err(), Some(NOT_FOUND), "{absent}");
        }
        assert_eq!(body(&site, "/a%zz").err(), Some(super::super::request::BAD_REQUEST));
        let without = Site::new(Page::Carried(PAGE), None);
        assert_eq!(body(&without, "/firmware/polyturn-9.9.9-stm32f411ce.bin").err(), Some(NOT_FOUND));
    }

    #[test]
    fn a_folder_page_still_gets_the_carried_firmware() {
        let d = std::env::temp_dir().join(format!("polyturn-web-site-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("index.html"), b"on disk").unwrap();
        let site = Site::new(Page::Folder(std::fs::canonicalize(&d).unwrap()), Some(FW));
        let index = site.find("/").map(|f| (matches!(f.body, Body::File(_)), f.len));
        let fw = body(&site, &format!("/{}", FW.url_path()));
        let _ = std::fs::remove_dir_all(&d);
        assert_eq!(index, Ok((true, 7)));
        assert_eq!(fw, Ok((&b"image"[..], "application/octet-stream")));
    }
}
