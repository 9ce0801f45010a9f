"""GPIO ports (RM0383 §8), SYSCFG_EXTICR (§7.2.3-7.2.6) and EXTI (§10.3).

The harness drives input pins with `drive(port, pin, level)`; `None`
leaves a pin floating, where the configured pull decides its level
(§8.3.1: pull-up reads 1, pull-down 0; a floating pin with no pull reads
0 here). An edge on a pin's input level reaches EXTI when SYSCFG routes
that line to the port."""
from .base import Regs

MODER, OTYPER, OSPEEDR, PUPDR, IDR, ODR, BSRR, LCKR, AFRL, AFRH = (
    0x00, 0x04, 0x08, 0x0C, 0x10, 0x14, 0x18, 0x1C, 0x20, 0x24)
# §8.4.11 register map reset values: GPIOA has the SWD pins (PA13/14/15)
# in AF with pulls, GPIOB PB3/PB4 (JTAG) likewise
RESETS = {
    "A": {MODER: 0x0C00_0000, OSPEEDR: 0x0C00_0000, PUPDR: 0x6400_0000},
    "B": {MODER: 0x0000_0280, OSPEEDR: 0x0000_00C0, PUPDR: 0x0000_0100},
}


class Gpio(Regs):
    size = 0x400

    def __init__(self, machine, base, port):
        self.reset = RESETS.get(port, {})
        super().__init__(machine, base)
        self.port = port
        self.name = "GPIO" + port
        self.ext = [None] * 16     # what the outside world drives
        self.output_since = {}     # pin -> cycle its MODER became output
        self.last = self.levels()

    def field(self, off, pin, bits=2):
        return self.get(off) >> (pin * bits) & ((1 << bits) - 1)

    def afr(self, pin):
        return self.get(AFRL if pin < 8 else AFRH) >> ((pin % 8) * 4) & 0xF

    def level(self, pin):
        """The input level of a pin (§8.3.9-8.3.12)."""
        mode = self.field(MODER, pin)
        if mode == 1:                        # output: input buffer sees ODR
            return self.get(ODR) >> pin & 1
        if self.ext[pin] is not None:
            return self.ext[pin]
        return 1 if self.field(PUPDR, pin) == 1 else 0

    def levels(self):
        return [self.level(p) for p in range(16)]

    def read(self, off):
        if off == IDR:                       # §8.4.5, read-only
            return sum(b << p for p, b in enumerate(self.levels()))
        if off == BSRR:                      # §8.4.7: write-only, reads 0
            return 0
        return self.get(off)

    def write(self, off, value, mask):
        value &= mask
        if off == IDR:
            return
        if off == BSRR:
            # §8.4.7: BSy sets ODRy, BRy resets it; BS wins if both
            odr = self.get(ODR)
            odr &= ~(value >> 16) & 0xFFFF
            odr |= value & 0xFFFF
            self.r[ODR] = odr
        else:
            super().write(off, value, mask)
            if off == MODER:
                for p in range(16):
                    if self.field(MODER, p) == 1:
                        self.output_since.setdefault(p, self.m.now_exact())
            if off == ODR:
                self.r[ODR] &= 0xFFFF
        self.edges()

    def drive(self, pin, level):
        self.ext[pin] = level
        self.edges()

    def edges(self):
        now = self.levels()
        for pin, (a, b) in enumerate(zip(self.last, now)):
            if a != b:
                self.m.exti.edge(self.port, pin, rising=b == 1)
        self.last = now

    def pin_out(self, pin):
        """What the pin shows outside: ODR in output mode, else None (the
        alternate function or an input: the caller looks at the peripheral)."""
        return self.get(ODR) >> pin & 1 if self.field(MODER, pin) == 1 else None


class Syscfg(Regs):
    name = "SYSCFG"

    def port_of_line(self, line):
        """§7.2.3-7.2.6: EXTIx[3:0] in SYSCFG_EXTICR1..4 selects the port."""
        v = self.get(0x08 + 4 * (line // 4)) >> (4 * (line % 4)) & 0xF
        return "ABCDEFGH"[v] if v < 8 else "?"


class Exti(Regs):
    name = "EXTI"
    IMR, EMR, RTSR, FTSR, SWIER, PR = 0x00, 0x04, 0x08, 0x0C, 0x10, 0x14

    def edge(self, port, pin, rising):
        """§10.2.3/§10.3: an edge on line `pin` (when SYSCFG routes the port
        to it) sets PR if its trigger is selected."""
        if self.m.syscfg.port_of_line(pin) != port:
            return
        trig = self.RTSR if rising else self.FTSR
        if self.get(trig) >> pin & 1:
            self.r[self.PR] = self.get(self.PR) | 1 << pin
            self.m.log_event("EXTI%d %s edge on P%s%d" % (pin, "rising" if rising else "falling", port, pin))

    def write(self, off, value, mask):
        value &= mask
        if off == self.PR:
            # §10.3.6: rc_w1, writing 1 clears the pending bit
            self.r[self.PR] = self.get(self.PR) & ~value
        elif off == self.SWIER:
            # §10.3.5: writing 1 sets PR when the line is unmasked
            self.r[self.PR] = self.get(self.PR) | value & self.get(self.IMR)
        else:
            super().write(off, value, mask)

    def line_pending(self, lo, hi):
        """The level EXTI drives into the NVIC for lines lo..hi: PR & IMR."""
        bits = self.get(self.PR) & self.get(self.IMR)
        return bool(bits >> lo & ((1 << (hi - lo + 1)) - 1))
