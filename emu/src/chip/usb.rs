//! USB OTG_FS (RM0383 §22) as a stub, on the documented list of what is not
//! modelled: registers as memory, plus what embassy-usb-synopsys-otg waits for in
//! its init: GRSTCTL.AHBIDL set and CSRST/TXFFLSH/RXFFLSH done at once (§22.16.4),
//! GINTSTS.CMOD = 0 (device mode) with its rc_w1 flags (§22.16.5), CID 0x1200
//! (§22.16.11). No host is ever attached: no bus events, no transfers, no interrupt.

use polyturn_stm32_model::chip::RegFile;

const GRSTCTL: u32 = 0x10;
const GINTSTS: u32 = 0x14;
const CID: u32 = 0x3C;

pub struct UsbStub {
    regs: RegFile,
}

impl Default for UsbStub {
    fn default() -> UsbStub {
        UsbStub { regs: RegFile::new(&[(GRSTCTL, 0x8000_0000), (GINTSTS, 0x0400_0020), (CID, 0x0000_1200)]) }
    }
}

impl UsbStub {
    pub fn read(&self, off: u32) -> u32 {
        match off {
            GRSTCTL => self.regs.get(off) | 1 << 31,
            GINTSTS => self.regs.get(off) & !1,
            _ => self.regs.get(off),
        }
    }

    pub fn write(&mut self, off: u32, v: u32, m: u32) {
        match off {
            GRSTCTL => self.regs.write(off, v & !0x31, m),
            GINTSTS => self.regs.set(off, self.regs.get(off) & !(v & m & 0xF030_FC0A)),
            _ => self.regs.write(off, v, m),
        }
    }

    pub fn irq(&self) -> bool {
        false
    }
}
