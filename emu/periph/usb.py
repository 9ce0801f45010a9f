"""USB OTG_FS core (RM0383 §22) as a stub: registers as memory, plus what
embassy-usb-synopsys-otg waits for during its init: GRSTCTL.AHBIDL set and
CSRST/TxFFLSH/RxFFLSH self-clearing (§22.16.4), GINTSTS.CMOD = 0 (device
mode, §22.16.5; its flags are rc_w1), CID = 0x0000_1200 (§22.16.11). No
host is ever attached: no bus events, no transfers."""
from .base import Regs

GRSTCTL, GINTSTS, CID = 0x10, 0x14, 0x3C


class Usb(Regs):
    name = "OTG_FS"
    size = 0x4_0000
    reset = {GRSTCTL: 0x8000_0000, GINTSTS: 0x0400_0020, CID: 0x0000_1200}

    def read(self, off):
        if off == GRSTCTL:
            return self.get(off) | 1 << 31
        if off == GINTSTS:
            return self.get(off) & ~1
        return self.get(off)

    def write(self, off, value, mask):
        v = value & mask
        if off == GRSTCTL:
            super().write(off, value & ~0x31, mask)   # CSRST, RXFFLSH, TXFFLSH done at once
        elif off == GINTSTS:
            self.r[off] = self.get(off) & ~(v & 0xF030_FC0A)  # rc_w1 bits
        elif off == CID:
            super().write(off, value, mask)
        else:
            super().write(off, value, mask)

    def irq_level(self):
        # GINTSTS & GINTMSK with GAHBCFG.GINTMSK: never with no host events
        return False
