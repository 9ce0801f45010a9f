"""The peripheral address space (RM0383 §2.3 memory map, PM0214 §4 for the
private peripheral bus): dispatches each access to its model; an access
no model claims is logged once per address and reads as 0, so a new
peripheral shows up clearly."""
import bisect


class Bus:
    def __init__(self, machine):
        self.m = machine
        self.starts = []
        self.models = []
        self.unmapped = {}   # addr -> (first access kind, function)

    def add(self, model):
        i = bisect.bisect(self.starts, model.base)
        self.starts.insert(i, model.base)
        self.models.insert(i, model)
        return model

    def find(self, addr):
        i = bisect.bisect_right(self.starts, addr) - 1
        if i >= 0:
            mod = self.models[i]
            if addr < mod.base + mod.size:
                return mod
        return None

    def _unmapped(self, addr, kind, value=None):
        if addr not in self.unmapped:
            where = self.m.image.func_at(self.m.pc())
            self.unmapped[addr] = (kind, where)
            self.m.log("unmapped %s 0x%08x%s in %s" % (kind, addr, "" if value is None else " = 0x%x" % value, where))

    def read(self, addr, size):
        word = addr & ~3
        mod = self.find(word)
        if mod is None:
            self._unmapped(addr, "read")
            return 0
        self.m.sync()
        v = mod.read(word - mod.base)
        return (v >> ((addr & 3) * 8)) & ((1 << (8 * size)) - 1)

    def write(self, addr, size, value):
        word = addr & ~3
        mod = self.find(word)
        if mod is None:
            self._unmapped(addr, "write", value)
            return
        self.m.sync()
        shift = (addr & 3) * 8
        mask = ((1 << (8 * size)) - 1) << shift
        mod.write(word - mod.base, (value << shift) & mask, mask)
        self.m.after_write()
