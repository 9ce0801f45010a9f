//! USB OTG_FS: `polyturn_stm32_model::chip::otg`'s core (RM0383 §22) on the bus,
//! with the emulated host (`crate::usb::host`) on its cable when a scenario plugs
//! one in. The host acts between slices: its next slot is a `Chip::next_event`.
//! A model's "not modelled" panic (an access the core does not implement) becomes
//! a fault of the run naming it.

use super::{bus::caught, Chip};

impl Chip {
    pub(super) fn usb_read(&mut self, off: u32) -> u32 {
        caught(|| self.usb.read(off)).unwrap_or_else(|e| {
            self.fault(e);
            0
        })
    }

    pub(super) fn usb_write(&mut self, off: u32, v: u32, m: u32) {
        if let Err(e) = caught(|| self.usb.write(off, v, m)) {
            self.fault(e);
        }
    }

    /// The host's slots due by now (between slices).
    pub(super) fn usb_step(&mut self) {
        let (now, sysclk) = (self.now, self.sysclk());
        let Some(h) = self.host.as_mut() else { return };
        let usb = &mut self.usb;
        if let Err(e) = caught(|| h.step(now, sysclk, usb)) {
            self.fault(e);
        }
    }

    /// The host's next slot, if one is plugged in.
    pub(super) fn usb_next(&self) -> Option<u64> {
        self.host.as_ref().map(|h| h.next_event())
    }
}
