"""TIM1 (advanced, RM0383 §12), TIM2-5 (general purpose, §13), TIM9-11
(§14): one model. The counter counts up at CK_CNT = timer clock/(PSC+1)
(§13.3.1), only with CEN set and no slave mode (encoder and external clock
modes count nothing here: no encoder edges and no step pulses are fed).
At each overflow the repetition counter (TIM1, §12.3.3) decides on an
update event: shadow registers load (PSC always, ARR if ARPE, CCRx if
OCxPE: §13.3.1, §13.3.9), UIF is set and, with UDE, a DMA request goes out
(§12.3.19). A compare match (CNT = CCRx) sets CCxIF (§13.3.8). SR flags
are rc_w0 (§13.4.5). Interrupt lines are (SR & DIER) per timer."""
from .base import Regs

CR1, CR2, SMCR, DIER, SR, EGR, CCMR1, CCMR2, CCER, CNT, PSC, ARR, RCR = (
    0x00, 0x04, 0x08, 0x0C, 0x10, 0x14, 0x18, 0x1C, 0x20, 0x24, 0x28, 0x2C, 0x30)
CCR = [0x34, 0x38, 0x3C, 0x40]
BDTR, DCR, DMAR = 0x44, 0x48, 0x4C
CEN, UDIS, URS, ARPE = 1, 2, 4, 0x80
UDE = 1 << 8


class Timer(Regs):
    def __init__(self, machine, base, name, apb, bits=16, channels=4):
        super().__init__(machine, base)
        self.name, self.apb, self.bits, self.channels = name, apb, bits, channels
        self.max = (1 << bits) - 1
        self.r[ARR] = self.max            # §13.4.12 ARR resets to all ones
        self.cnt = 0
        self.pc = 0                       # prescaler counter
        self.rem = 0                      # timer clocks not yet whole (x sysclk)
        self.t = 0                        # cycle count advanced to
        self.psc = 0                      # shadow PSC
        self.arr = self.max               # shadow ARR
        self.rcr = 0                      # shadow RCR and repetition counter
        self.rep = 0
        self.ccr = [0] * 4                # shadow CCRx
        self.burst = 0                    # DMAR burst index (§12.4.20)
        self.updates = 0                  # update events, for the checks
        self.dma = None                   # callback for a UDE request

    # --- clocks ---
    def clk(self):
        return (self.m.rcc.apb1() if self.apb == 1 else self.m.rcc.apb2())[1]

    def counting(self):
        c1 = self.get(CR1)
        return c1 & CEN and self.get(SMCR) & 7 == 0 and self.arr != 0

    def advance(self, now):
        if now <= self.t:
            return
        dt, self.t = now - self.t, now
        sysclk = self.m.rcc.sysclk()
        self.rem += dt * self.clk()
        ticks, self.rem = divmod(self.rem, sysclk)
        if not self.counting() or ticks == 0:
            return
        incs, self.pc = divmod(self.pc + ticks, self.psc + 1)
        self.count(incs)

    def count(self, incs):
        while incs > 0:
            top = self.arr if self.cnt <= self.arr else self.max
            to_ovf = top - self.cnt + 1
            k = min(incs, to_ovf)
            lo, hi = self.cnt + 1, self.cnt + k          # values visited
            for i in range(self.channels):
                c = self.ccr[i]
                if lo <= c <= hi or (k == to_ovf and c == 0):
                    self.r[SR] = self.get(SR) | 2 << i       # CCxIF
            incs -= k
            if k == to_ovf:
                self.cnt = 0
                self.overflow()
            else:
                self.cnt = hi

    def overflow(self):
        if self.rep > 0:                  # §12.3.3 repetition counter
            self.rep -= 1
            return
        if self.get(CR1) & UDIS:
            return
        self.update_event()
        if self.get(DIER) & UDE and self.dma:
            self.dma(self)

    def load_shadows(self):
        self.psc = self.get(PSC) & 0xFFFF
        self.arr = self.get(ARR) & self.max
        self.rcr = self.get(RCR) & 0xFF
        self.rep = self.rcr
        for i in range(self.channels):
            self.ccr[i] = self.get(CCR[i]) & self.max

    def update_event(self):
        self.load_shadows()
        self.r[SR] = self.get(SR) | 1     # UIF
        self.updates += 1

    def preload(self, i):
        """OCxPE of channel i (CCMRx bit 3 / 11, §13.4.7)."""
        return self.get(CCMR1 if i < 2 else CCMR2) >> (3 + 8 * (i % 2)) & 1

    # --- registers ---
    def read(self, off):
        if off == CNT:
            return self.cnt
        if off == EGR:
            return 0
        if off == DMAR:
            return self.get(self.dmar_target())
        return self.get(off)

    def dmar_target(self):
        dcr = self.get(DCR)
        return ((dcr & 0x1F) + self.burst) * 4

    def write(self, off, value, mask):
        v = value & mask
        if off == SR:
            self.r[SR] = self.get(SR) & (value | ~mask)  # rc_w0
        elif off == CNT:
            self.cnt = (self.cnt & ~mask | v) & self.max
        elif off == EGR:
            if v & 1:                      # UG, §13.4.6
                self.cnt = 0
                self.pc = 0
                self.load_shadows()
                if not self.get(CR1) & URS:
                    self.r[SR] = self.get(SR) | 1
                    if self.get(DIER) & UDE and self.dma:
                        self.dma(self)
            for i in range(self.channels):  # CCxG sets CCxIF
                if v >> (i + 1) & 1:
                    self.r[SR] = self.get(SR) | 2 << i
        elif off == DMAR:
            # §12.4.20: each DMAR access goes to DBA + index; the index
            # wraps after DBL + 1 transfers
            target = self.dmar_target()
            self.burst = (self.burst + 1) % ((self.get(DCR) >> 8 & 0x1F) + 1)
            self.write(target, value, mask)
        else:
            super().write(off, value, mask)
            if off == ARR and not self.get(CR1) & ARPE:
                self.arr = self.get(ARR) & self.max
            elif off in CCR and not self.preload(CCR.index(off)):
                self.ccr[CCR.index(off)] = self.get(off) & self.max

    def irq_level(self, flags=0xFF):
        return bool(self.get(SR) & self.get(DIER) & flags)

    def next_event(self, now):
        """Cycle count of the next update or compare event that raises an
        interrupt or a DMA request, or None."""
        dier = self.get(DIER)
        if not self.counting() or not dier & (UDE | 0x1F):
            return None
        top = self.arr if self.cnt <= self.arr else self.max
        cands = []
        if dier & (UDE | 1):
            cands.append(top - self.cnt + 1 + self.rep * (self.arr + 1))
        for i in range(self.channels):
            if dier >> (i + 1) & 1:
                d = (self.ccr[i] - self.cnt) % (top + 1)
                cands.append(d if d else top + 1)
        incs = min(cands)
        ticks = (incs - 1) * (self.psc + 1) + (self.psc + 1 - self.pc)
        sysclk, clk = self.m.rcc.sysclk(), self.clk()
        cycles = -(-(ticks * sysclk - self.rem) // clk)
        return self.t + max(1, cycles)

    # --- what the output pins show ---
    def oc_ref(self, ch):
        """OCxREF from OCxM (§12.4.7): frozen, active/inactive on match,
        toggle are treated as their last level (not modelled: 0); forced
        levels and the PWM modes are exact."""
        m = self.get(CCMR1 if ch < 2 else CCMR2) >> (4 + 8 * (ch % 2)) & 7
        c = self.ccr[ch]
        return {4: 0, 5: 1, 6: int(self.cnt < c), 7: int(self.cnt >= c)}.get(m, 0)

    def oc_mode(self, ch):
        return self.get(CCMR1 if ch < 2 else CCMR2) >> (4 + 8 * (ch % 2)) & 7

    def oc_out(self, ch):
        """The level of OCx at its pin, or None if the output is off
        (CCxE = 0, or MOE = 0 on TIM1: §12.4.9 table 71, idle state)."""
        ccer = self.get(CCER)
        if not ccer >> (4 * ch) & 1:
            return None
        if self.name == "TIM1" and not self.get(BDTR) >> 15 & 1:
            return None
        return self.oc_ref(ch) ^ (ccer >> (4 * ch + 1) & 1)
