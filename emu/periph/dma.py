"""DMA2 (RM0383 §9): registers, and the one transfer path the firmware
uses: a timer's update DMA request served by a stream in memory-to-
peripheral direct mode (§9.3.12), one word per transfer, memory address
incremented, NDTR decremented and reloaded in circular mode (§9.3.9).
Requests are served at once (no bus arbitration or latency: §9.3.x
timing is not modelled); the FIFO and double-buffer modes are not."""
from .base import Regs

LISR, HISR, LIFCR, HIFCR = 0x00, 0x04, 0x08, 0x0C
EN, CIRC, MINC = 1, 1 << 8, 1 << 10
# flag bit offsets of streams 0..3 in LISR/HISR (§9.5.1): 0, 6, 16, 22
FLAG_SHIFT = [0, 6, 16, 22]


def sreg(stream, reg):
    """SxCR=0, SxNDTR=4, SxPAR=8, SxM0AR=0xC, SxM1AR=0x10, SxFCR=0x14."""
    return 0x10 + 0x18 * stream + reg


class Dma(Regs):
    def __init__(self, machine, base, name):
        super().__init__(machine, base)
        self.name = name
        for s in range(8):
            self.r[sreg(s, 0x14)] = 0x21           # SxFCR reset (§9.5.10)
        self.start = [0] * 8                        # NDTR programmed at enable
        self.pos = [0] * 8                          # items transferred
        self.transfers = 0

    def write(self, off, value, mask):
        v = value & mask
        if off in (LIFCR, HIFCR):                   # §9.5.3: write 1 clears
            isr = LISR if off == LIFCR else HISR
            self.r[isr] = self.get(isr) & ~v
            return
        if off in (LISR, HISR):
            return
        if off >= 0x10:
            s, reg = divmod(off - 0x10, 0x18)
            en = self.get(sreg(s, 0)) & EN
            if reg in (4, 8, 0xC) and en:
                return                              # read-only while enabled
            super().write(off, value, mask)
            if reg == 0 and v & EN and not en:
                self.start[s] = self.get(sreg(s, 4)) & 0xFFFF
                self.pos[s] = 0
            return
        super().write(off, value, mask)

    def flag(self, s, bit):
        isr = LISR if s < 4 else HISR
        self.r[isr] = self.get(isr) | 1 << (FLAG_SHIFT[s % 4] + bit)

    def request(self, s, channel, items, write_periph):
        """Serve `items` transfers of stream s for a request on `channel`."""
        cr = self.get(sreg(s, 0))
        if not cr & EN or cr >> 25 & 7 != channel:
            return
        for _ in range(items):
            ndtr = self.get(sreg(s, 4))
            if ndtr == 0:
                return
            addr = self.get(sreg(s, 0xC)) + (4 * self.pos[s] if cr & MINC else 0)
            word = int.from_bytes(self.m.uc.mem_read(addr, 4), "little")
            write_periph(word)
            self.transfers += 1
            self.pos[s] += 1
            ndtr -= 1
            if ndtr == self.start[s] // 2:
                self.flag(s, 4)                     # HTIF
            if ndtr == 0:
                self.flag(s, 5)                     # TCIF
                if cr & CIRC:
                    ndtr, self.pos[s] = self.start[s], 0
                else:
                    self.r[sreg(s, 0)] = cr & ~EN
            self.r[sreg(s, 4)] = ndtr


def tim1_up_to_dma2_s5(machine):
    """TIM1_UP is DMA2 stream 5 channel 6 (§9.3.3 table 28); with a DMA
    burst (TIMx_DCR) the timer asks for DBL + 1 transfers per update."""
    dma = machine.dma2

    def serve(tim):
        n = (tim.get(0x48) >> 8 & 0x1F) + 1
        dma.request(5, 6, n, lambda w: tim.write(0x4C, w, 0xFFFF_FFFF))
    return serve
