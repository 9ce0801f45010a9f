"""IWDG (RM0383 §17): KR/PR/RLR/SR. Every key written is recorded with
its time (0xCCCC start, 0xAAAA reload = pet, 0x5555 unlock PR/RLR,
§17.4.1). PR and RLR are writable only after 0x5555 (§17.3.4); their
update is instant, so SR's PVU/RVU read 0. The countdown itself (LSI 17-47
kHz) is not modelled: the checks look at the pets."""
from .base import Regs


class Iwdg(Regs):
    name = "IWDG"
    reset = {0x08: 0xFFF}

    def __init__(self, machine, base):
        super().__init__(machine, base)
        self.keys = []        # (cycle, key)
        self.unlocked = False

    def read(self, off):
        return 0 if off in (0x00, 0x0C) else self.get(off)

    def write(self, off, value, mask):
        v = value & mask
        if off == 0x00:
            key = v & 0xFFFF
            self.keys.append((self.m.now_exact(), key))
            self.unlocked = key == 0x5555
            if key in (0xAAAA, 0xCCCC):
                self.unlocked = False
        elif off in (0x04, 0x08) and self.unlocked:
            super().write(off, value, mask)

    def started_at(self):
        return next((t for t, k in self.keys if k == 0xCCCC), None)

    def pets(self):
        return [t for t, k in self.keys if k == 0xAAAA]
