//! What a release `polyturn` carries (feature `embed`, see build.rs): the
//! page's files and the release firmware image. Without the feature there
//! is nothing, and `polyturn web` and `polyturn flash` look in the
//! checkout instead. Callers take these as arguments, so that their tests
//! run without the feature.

/// The page's files, by name under the page's folder ("pkg/x.wasm").
pub type Page = &'static [(&'static str, &'static [u8])];

/// A firmware image in the binary: its release file name and bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Firmware {
    pub name: &'static str,
    pub bytes: &'static [u8],
}

impl Firmware {
    /// Where `polyturn web` serves it: a fixed path the page can find.
    pub fn url_path(&self) -> String {
        format!("firmware/{}", self.name)
    }
}

#[cfg(feature = "embed")]
mod generated {
    include!(concat!(env!("OUT_DIR"), "/embedded.rs"));
}

/// The page, or None if this build carries none.
pub fn page() -> Option<Page> {
    #[cfg(feature = "embed")]
    return Some(generated::PAGE);
    #[cfg(not(feature = "embed"))]
    None
}

/// The release image, or None if this build carries none.
pub fn firmware() -> Option<Firmware> {
    #[cfg(feature = "embed")]
    return Some(Firmware { name: generated::FIRMWARE.0, bytes: generated::FIRMWARE.1 });
    #[cfg(not(feature = "embed"))]
    None
}

#[cfg(all(test, feature = "embed"))]
mod tests {
    use crate::flash::image::{from_bytes, Format};

    #[test]
    fn the_carried_page_and_image_are_what_web_and_flash_need() {
        let page = super::page().unwrap();
        assert!(page.iter().any(|(n, b)| *n == "pkg/polyturn_web_bg.wasm" && !b.is_empty()));
        assert!(page.iter().any(|(n, _)| *n == "index.html"));
        let fw = super::firmware().unwrap();
        let image = from_bytes(fw.bytes, Format::Bin, false).unwrap();
        assert_eq!(image.version.as_deref(), Some(super::super::VERSION));
    }
}
