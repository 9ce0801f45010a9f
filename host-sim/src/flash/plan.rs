//! What a flash will send, decided before the first request: the device
//! checked (DfuSe 1.1a, its flash at FLASH_BASE, pages that end by the
//! settings), the image padded to whole transfers and the sectors its
//! erase takes. Shared by `polyturn flash` (`dfuse.rs`) and the web page,
//! which runs the same requests over WebUSB.

use super::Image;
use super::{APP_END, FLASH_BASE};
use dfu_core::functional_descriptor::FunctionalDescriptor;
use dfu_core::memory_layout::mem;
use dfu_core::DfuProtocol;

/// What goes over the wire: the image padded with 0xFF (erased flash) to
/// whole transfers, so that every DNLOAD and UPLOAD block is full size and
/// block n is at FLASH_BASE + (n − 2) × wTransferSize (AN3156 §4.1, §5.1)
/// whichever size the ROM counts with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    pub bytes: Vec<u8>,
    pub transfer: usize,
    pub sectors: usize,
    /// where each erased page starts (AN3156 §5.3: one erase per page)
    pub pages: Vec<u32>,
}

/// Refuses a device whose erase would reach the settings: the device's
/// pages are erased from its start address until the image's end is
/// covered, so those pages must end by APP_END.
pub fn plan<M: AsRef<mem>>(d: &FunctionalDescriptor, protocol: &DfuProtocol<M>, image: &Image) -> Result<Plan, String> {
    let transfer = usize::from(d.transfer_size);
    if d.dfu_version != (0x01, 0x1A) || !d.can_download || !d.can_upload || transfer < 64 {
        return Err(format!(
            "not the STM32 ROM bootloader's DfuSe 1.1a: version {:x?}, transfer size {transfer}",
            d.dfu_version
        ));
    }
    let DfuProtocol::Dfuse { address, memory_layout } = protocol else {
        return Err("the device speaks plain DFU, not DfuSe".into());
    };
    if image.base != FLASH_BASE || *address != FLASH_BASE {
        return Err(format!("the device's flash starts at 0x{address:08x}, not 0x{FLASH_BASE:08x}"));
    }
    let mut bytes = image.bytes.clone();
    bytes.resize(bytes.len().div_ceil(transfer) * transfer, 0xFF);
    let end = u64::from(FLASH_BASE) + bytes.len() as u64;
    let (mut erased_end, mut pages) = (u64::from(FLASH_BASE), Vec::new());
    for page in memory_layout.as_ref() {
        if erased_end >= end {
            break;
        }
        pages.push(erased_end as u32);
        erased_end += u64::from(*page);
    }
    if erased_end < end {
        return Err(format!("the device's flash ends at 0x{erased_end:08x}, before the image does"));
    }
    if erased_end > u64::from(APP_END) {
        let why = format!("the device's flash pages would erase up to 0x{erased_end:08x}, past 0x{APP_END:08x}");
        return Err(format!("{why} (sectors 6-7 keep the settings)"));
    }
    Ok(Plan { bytes, transfer, sectors: pages.len(), pages })
}

/// The web page's plan: the interface string as WebUSB gives it
/// (`interfaceName`) and the DFU functional descriptor's bytes as the page
/// read them from the device's configuration descriptor (DFU 1.1 §4.1.3),
/// so the page refuses what `polyturn flash` refuses.
pub fn plan_for_web(interface: &str, functional: &[u8], image: &Image) -> Result<Plan, String> {
    let d = match FunctionalDescriptor::from_bytes(functional) {
        Some(Ok(d)) => d,
        Some(Err(_)) | None => {
            return Err(format!("the device's DFU functional descriptor is not one (bytes {functional:02x?})"));
        }
    };
    let protocol = DfuProtocol::new(interface, d.dfu_version)
        .map_err(|e| format!("the device's interface '{interface}' is not a DfuSe memory layout: {e}"))?;
    plan(&d, &protocol, image)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flash::image::Format;
    use polyturn_bench::flash::fake::INTERFACE;
    use polyturn_bench::flash::testkit::good;

    #[test]
    fn the_web_plan_pads_to_whole_transfers_and_erases_the_pages_the_image_covers() {
        let image = crate::flash::image::from_bytes(&good(40 * 1024 + 4), Format::Bin, false).unwrap();
        assert_eq!(image.bytes.len(), 40 * 1024 + 16, "with its seal");
        let p = plan_for_web(INTERFACE, &rom_descriptor(), &image).unwrap();
        assert_eq!(p.bytes.len(), 42 * 1024, "41 KiB rounds up to 21 transfers of 2 KiB");
        assert!(p.bytes[40 * 1024 + 16..].iter().all(|&b| b == 0xFF));
        assert_eq!(p.pages, vec![0x0800_0000, 0x0800_4000, 0x0800_8000], "three 16 KiB sectors");
    }

    #[test]
    fn a_device_whose_pages_would_erase_the_settings_is_refused() {
        let image = crate::flash::image::from_bytes(&good(1024), Format::Bin, false).unwrap();
        let e = plan_for_web("@Internal Flash  /0x08000000/01*512Kg", &rom_descriptor(), &image).unwrap_err();
        assert!(e.contains("past 0x08040000 (sectors 6-7 keep the settings)"), "{e}");
        let e = plan_for_web("not a layout", &rom_descriptor(), &image).unwrap_err();
        assert!(e.starts_with("the device's interface 'not a layout'"), "{e}");
    }

    /// The fake ROM's functional descriptor, the last 9 bytes of its
    /// configuration descriptor.
    fn rom_descriptor() -> [u8; 9] {
        let config = polyturn_bench::flash::fake::FakeRom::new(Default::default()).configuration_descriptor();
        config[config.len() - 9..].try_into().unwrap()
    }

    #[test]
    fn the_web_plan_refuses_what_polyturn_flash_refuses_in_the_descriptor() {
        let image = crate::flash::image::from_bytes(&good(1024), Format::Bin, false).unwrap();
        let with = |bytes: &[(usize, u8)]| {
            let mut d = rom_descriptor();
            for &(i, v) in bytes {
                d[i] = v;
            }
            plan_for_web(INTERFACE, &d, &image).map(|_| ())
        };
        assert_eq!(with(&[]), Ok(()), "the ROM's own");
        // plain DFU 1.1, no upload, a 32-byte transfer
        for bad in [&[(7, 0x10)][..], &[(2, 0x09)], &[(5, 32), (6, 0)]] {
            let e = with(bad).unwrap_err();
            assert!(e.starts_with("not the STM32 ROM bootloader's DfuSe 1.1a"), "{bad:?}: {e}");
        }
        // not a functional descriptor (type 0x04), or cut short
        let e = with(&[(1, 0x04)]).unwrap_err();
        assert!(e.starts_with("the device's DFU functional descriptor is not one"), "{e}");
        let e = plan_for_web(INTERFACE, &rom_descriptor()[..5], &image).unwrap_err();
        assert!(e.starts_with("the device's DFU functional descriptor is not one"), "{e}");
    }
}
