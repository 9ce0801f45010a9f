"""Registers as memory: the default behaviour of every model here. A
register reads back what was written (RM0383 §1.2: rw bits) unless a model
overrides read/write for the bits the manual defines otherwise."""


class Regs:
    name = "?"
    size = 0x400
    reset = {}          # offset -> reset value (RM0383 register maps)

    def __init__(self, machine, base):
        self.m = machine
        self.base = base
        self.r = dict(self.reset)
        self.writes = []  # (offset, value) log, for checks that want history

    def get(self, off):
        return self.r.get(off, 0)

    def read(self, off):
        return self.get(off)

    def write(self, off, value, mask):
        """A (possibly partial) write: value and mask already shifted into
        the 32-bit word at off."""
        self.r[off] = (self.get(off) & ~mask | value & mask) & 0xFFFF_FFFF

    # time-dependent models override these
    def advance(self, now):
        pass

    def next_event(self, now):
        return None
