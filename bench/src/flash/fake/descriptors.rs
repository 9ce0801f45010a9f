//! The fake ROM's USB descriptors as the page reads them with a standard
//! GET_DESCRIPTOR (USB 2.0 §9.4.3; the descriptors §9.6.3, §9.6.5): one
//! configuration, one DFU interface whose alternate settings are the ROM's
//! memories (`dfu-util -l` on an STM32F4 ROM lists four: @Internal Flash,
//! @Option Bytes, @OTP Memory, @Device Feature), then the DFU functional
//! descriptor (DFU 1.1 §4.1.3).

use super::FakeRom;
use dfu_core::functional_descriptor::FunctionalDescriptor;

/// DFU 1.1 §4.1.3: bLength 9, type 0x21, bmAttributes, wDetachTimeOut,
/// wTransferSize, bcdDFUVersion (little-endian).
fn functional_descriptor_bytes(d: &FunctionalDescriptor) -> [u8; 9] {
    let attributes = u8::from(d.can_download)
        | u8::from(d.can_upload) << 1
        | u8::from(d.manifestation_tolerant) << 2
        | u8::from(d.will_detach) << 3;
    let [t0, t1] = d.detach_timeout.to_le_bytes();
    let [s0, s1] = d.transfer_size.to_le_bytes();
    [9, 0x21, attributes, t0, t1, s0, s1, d.dfu_version.1, d.dfu_version.0]
}

impl FakeRom {
    /// The configuration descriptor with everything under it (wTotalLength
    /// bytes), as the STM32 ROM's: four alternate settings of interface 0.
    pub fn configuration_descriptor(&self) -> Vec<u8> {
        let mut out = vec![9, 0x02, 0, 0, 1, 1, 0, 0xC0, 0x32];
        for alternate in 0..4u8 {
            // class 0xFE (application specific), subclass 1 (DFU), protocol 2 (DFU mode)
            out.extend([9, 0x04, 0, alternate, 0, 0xFE, 0x01, 0x02, 4 + alternate]);
        }
        out.extend(functional_descriptor_bytes(&self.descriptor));
        let total = (out.len() as u16).to_le_bytes();
        out[2..4].copy_from_slice(&total);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_functional_descriptor_is_the_stm32_roms() {
        // lsusb -v of 0483:df11: bmAttributes 0x0b (will detach, upload,
        // download), wDetachTimeout 255 ms, wTransferSize 2048, bcdDFUVersion 1.1a
        let config = FakeRom::new(Default::default()).configuration_descriptor();
        assert_eq!(config[config.len() - 9..], [0x09, 0x21, 0x0B, 0xFF, 0x00, 0x00, 0x08, 0x1A, 0x01]);
        assert_eq!(usize::from(u16::from_le_bytes([config[2], config[3]])), config.len());
    }
}
