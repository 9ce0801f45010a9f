//! Flashing from the page: the image checked and planned by the host
//! library (`flash::image`, `flash::plan`, the same rules as `polyturn
//! flash`), and the fake ROM bootloader the page's WebUSB layer is tested
//! against (`polyturn_bench::flash::fake`, the one `polyturn flash`'s DfuSe is tested
//! against).

use dfu_core::DfuIo;
use polyturn_bench::flash::fake::{FakeRom, Faults};
use polyturn_host::flash::plan::plan_for_web;
use polyturn_host::flash::{image, Refusal};
use std::path::Path;
use wasm_bindgen::prelude::*;

/// What the page sends: the padded bytes, the transfer size, the pages to
/// erase (their start addresses), and the image's version and SHA-256.
#[wasm_bindgen(getter_with_clone)]
pub struct FlashPlan {
    pub bytes: Vec<u8>,
    pub transfer: usize,
    pub pages: Vec<u32>,
    pub image_len: usize,
    pub version: Option<String>,
    pub sha256: String,
}

/// Checks `file` (named `name`: .bin, .hex or an ELF) for the device whose
/// DFU interface string is `interface` and DFU functional descriptor is
/// `functional` (its 9 bytes); the error says which rule failed.
#[wasm_bindgen(js_name = flash_plan)]
pub fn plan_image(name: &str, file: &[u8], interface: &str, functional: &[u8]) -> Result<FlashPlan, String> {
    let refused = |r: Refusal| format!("{name} {} ({})", r.rule, r.found);
    let format = image::format_of(Path::new(name), file).map_err(refused)?;
    let img = image::from_bytes(file, format, false).map_err(refused)?;
    let plan = plan_for_web(interface, functional, &img)?;
    Ok(FlashPlan {
        bytes: plan.bytes,
        transfer: plan.transfer,
        pages: plan.pages,
        image_len: img.bytes.len(),
        version: img.version,
        sha256: img.sha256,
    })
}

/// The fake STM32F411 ROM bootloader, its control transfers as WebUSB's
/// `controlTransferIn/Out` make them (class requests to the interface).
#[wasm_bindgen]
pub struct FakeDfu {
    rom: FakeRom,
}

#[wasm_bindgen]
impl FakeDfu {
    /// `stuck_address`/`stuck_mask`: a weak cell whose bits stay 0 when
    /// programmed (0 for none), so a verify failure can be shown.
    #[wasm_bindgen(constructor)]
    pub fn new(stuck_address: u32, stuck_mask: u8) -> FakeDfu {
        let stuck_low = (stuck_mask != 0).then_some((stuck_address, stuck_mask));
        FakeDfu { rom: FakeRom::new(Faults { stuck_low, ..Faults::default() }) }
    }

    /// The alternate setting's name, as WebUSB's `interfaceName`.
    pub fn interface(&self) -> String {
        polyturn_bench::flash::fake::INTERFACE.into()
    }

    /// The configuration descriptor, as a standard GET_DESCRIPTOR reads it.
    pub fn configuration_descriptor(&self) -> Vec<u8> {
        self.rom.configuration_descriptor()
    }

    /// A device-to-host request; Err is a stall or a USB error.
    pub fn control_in(&self, request: u8, value: u16, length: usize) -> Result<Vec<u8>, String> {
        let mut buf = vec![0u8; length];
        let n = self.rom.read_control(0xA1, request, value, &mut buf).map_err(|e| e.0)?;
        buf.truncate(n);
        Ok(buf)
    }

    /// A host-to-device request; Ok is the bytes taken.
    pub fn control_out(&self, request: u8, value: u16, data: &[u8]) -> Result<usize, String> {
        self.rom.write_control(0x21, request, value, data).map_err(|e| e.0)
    }

    /// Flash as the chip holds it now.
    pub fn read(&self, address: u32, len: usize) -> Vec<u8> {
        self.rom.read(address, len)
    }

    /// Every request the ROM acted on, one per line (for the tests).
    pub fn events(&self) -> Vec<String> {
        self.rom.events().iter().map(|e| format!("{e:?}")).collect()
    }

    /// A valid polyturn image of `len` bytes (the host's test kit's), to flash.
    pub fn sample_image(len: usize) -> Vec<u8> {
        polyturn_bench::flash::testkit::good(len)
    }

    /// Loads flash as if an earlier image were there.
    pub fn preload(&self, address: u32, bytes: &[u8]) {
        self.rom.preload(address, bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use polyturn_bench::flash::testkit::good;

    #[test]
    fn an_image_is_planned_as_polyturn_flash_plans_it() {
        let rom = FakeDfu::new(0, 0);
        let config = rom.configuration_descriptor();
        let p = plan_image("polyturn.bin", &good(5000), &rom.interface(), &config[config.len() - 9..]).unwrap();
        assert_eq!((p.image_len, p.bytes.len(), p.transfer), (5012, 6144, 2048), "5000 bytes and the seal");
        assert_eq!(p.pages, vec![0x0800_0000]);
        assert_eq!(p.version.as_deref(), Some(polyturn_host::cli::VERSION));
    }

    #[test]
    fn a_file_that_is_no_image_is_refused_naming_the_rule() {
        let e =
            plan_image("notes.bin", b"hello", "@Internal Flash  /0x08000000/04*016Kg", &[]).map(|_| ()).unwrap_err();
        assert!(e.starts_with("notes.bin "), "{e}");
    }
}
