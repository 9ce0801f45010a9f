"""The Cortex-M4 private peripheral bus (PM0214 §4): NVIC (§4.3), SCB
(§4.4), SysTick (§4.5, registers only: the firmware does not use it; a
start is logged), DWT CYCCNT and DCB DEMCR (ARMv7-M ARM C1.8, C1.6).
CYCCNT counts emulated instructions (1 instruction = 1 cycle) while
DEMCR.TRCENA and DWT_CTRL.CYCCNTENA are set."""
from periph.base import Regs

ISER, ICER, ISPR, ICPR, IABR, IPR = 0xE100, 0xE180, 0xE200, 0xE280, 0xE300, 0xE400
ICSR, VTOR, AIRCR, SHPR1, STIR = 0xED04, 0xED08, 0xED0C, 0xED18, 0xEF00
DWT_CTRL, DWT_CYCCNT, DEMCR = 0x1000, 0x1004, 0xEDFC
NIRQ = 86   # the F411's vector table: 16 + 86 entries (RM0383 §10.2 table 37)


class Ppb(Regs):
    name = "PPB"
    size = 0x10_0000
    # CPUID r0p1 Cortex-M4 (PM0214 §4.4.1), AIRCR VECTKEYSTAT, CCR STKALIGN,
    # FPCCR ASPEN|LSPEN, ICTR 2 (up to 96 IRQs), DWT_CTRL NUMCOMP = 4
    reset = {0xED00: 0x410F_C241, AIRCR: 0xFA05_0000, 0xED14: 0x0000_0200,
             0xEF34: 0xC000_0000, 0xE004: 2, DWT_CTRL: 0x4000_0000}

    def __init__(self, machine, base):
        super().__init__(machine, base)
        self.enabled = [False] * NIRQ
        self.pending = set()       # exception numbers (16 + IRQ, or 14/15)
        self.prio = [0] * (16 + NIRQ)
        self.cyc_base, self.cyc_at = 0, 0

    # --- priorities (PM0214 §4.3.7: only bits [7:4] are implemented) ---
    def set_prio_byte(self, exc, b):
        self.prio[exc] = b & 0xF0

    def group(self, p):
        """Group (pre-emption) priority under AIRCR.PRIGROUP (§4.4.5)."""
        g = self.get(AIRCR) >> 8 & 7
        return p & ~((2 << g) - 1) & 0xFF

    def cycles_on(self):
        return self.get(DEMCR) >> 24 & 1 and self.get(DWT_CTRL) & 1

    def read(self, off):
        if ISER <= off < ISER + 12 or ICER <= off < ICER + 12:
            base = ISER if off < ICER else ICER
            return self._bits(off - base, lambda n: self.enabled[n])
        if ISPR <= off < ISPR + 12 or ICPR <= off < ICPR + 12:
            base = ISPR if off < ICPR else ICPR
            return self._bits(off - base, lambda n: 16 + n in self.pending)
        if IABR <= off < IABR + 12:
            return self._bits(off - IABR, lambda n: 16 + n in self.m.active)
        if IPR <= off < IPR + NIRQ:
            return sum(self.prio[16 + off - IPR + i] << (8 * i) for i in range(4) if off - IPR + i < NIRQ)
        if SHPR1 <= off < SHPR1 + 12:
            return sum(self.prio[4 + off - SHPR1 + i] << (8 * i) for i in range(4))
        if off == ICSR:
            # VECTACTIVE, VECTPENDING, ISRPENDING, PENDSV/PENDST set bits
            cur = self.m.ipsr()
            pend = min(self.pending, key=lambda e: (self.prio[e], e), default=0)
            v = cur | pend << 12 | (bool(self.pending) << 22)
            v |= (14 in self.pending) << 28 | (15 in self.pending) << 26
            return v
        if off == DWT_CYCCNT:
            if self.cycles_on():
                return (self.cyc_base + self.m.now_exact() - self.cyc_at) & 0xFFFF_FFFF
            return self.cyc_base
        return self.get(off)

    def _bits(self, woff, test):
        return sum(1 << i for i in range(32) if 32 * (woff // 4) + i < NIRQ and test(32 * (woff // 4) + i))

    def write(self, off, value, mask):
        v = value & mask
        for base, act in ((ISER, "en"), (ICER, "dis"), (ISPR, "pend"), (ICPR, "unpend")):
            if base <= off < base + 12:
                for i in range(32):
                    n = 32 * ((off - base) // 4) + i
                    if v >> i & 1 and n < NIRQ:
                        if act == "en":
                            self.enabled[n] = True
                        elif act == "dis":
                            self.enabled[n] = False
                        elif act == "pend":
                            self.pending.add(16 + n)
                        else:
                            self.pending.discard(16 + n)
                return
        if IPR <= off < IPR + NIRQ:
            for i in range(4):
                if mask >> (8 * i) & 0xFF and off - IPR + i < NIRQ:
                    self.set_prio_byte(16 + off - IPR + i, v >> (8 * i))
            return
        if SHPR1 <= off < SHPR1 + 12:
            for i in range(4):
                if mask >> (8 * i) & 0xFF:
                    self.set_prio_byte(4 + off - SHPR1 + i, v >> (8 * i))
            return
        if off == STIR:                                # §4.3.8
            self.pending.add(16 + (v & 0x1FF))
            return
        if off == ICSR:                                # §4.4.3
            if v >> 28 & 1:
                self.pending.add(14)
            if v >> 27 & 1:
                self.pending.discard(14)
            if v >> 26 & 1:
                self.pending.add(15)
            if v >> 25 & 1:
                self.pending.discard(15)
            return
        if off == AIRCR:                               # §4.4.5: VECTKEY
            if v >> 16 != 0x05FA:
                return
            if v & 4:
                self.m.log("SYSRESETREQ: reset requested")
                self.m.reset_requested = True
            self.r[AIRCR] = 0xFA05_0000 | v & 0x700
            return
        if off == DWT_CYCCNT:
            self.cyc_base, self.cyc_at = v, self.m.now_exact()
            return
        if off in (DWT_CTRL, DEMCR):
            cur = self.read(DWT_CYCCNT)
            super().write(off, value, mask)
            self.cyc_base, self.cyc_at = cur, self.m.now_exact()
            return
        if off == 0xE010 and v & 1:
            self.m.log("SysTick enabled: not modelled")
        super().write(off, value, mask)
