"""RCC (RM0383 §6), PWR (§5) and the FLASH interface registers (§3).

Oscillators and the PLL are ready as soon as they are switched on (the
firmware only polls the flags), and the clock tree is computed from what
the firmware wrote, with the Black Pill's 25 MHz HSE crystal."""
from .base import Regs

HSI_HZ = 16_000_000   # §6.2.2
HSE_HZ = 25_000_000   # the WeAct Black Pill's crystal

CR, PLLCFGR, CFGR, CSR = 0x00, 0x04, 0x08, 0x74
AHB_DIV = {0b1000: 2, 0b1001: 4, 0b1010: 8, 0b1011: 16, 0b1100: 64, 0b1101: 128, 0b1110: 256, 0b1111: 512}
APB_DIV = {0b100: 2, 0b101: 4, 0b110: 8, 0b111: 16}


class Rcc(Regs):
    name = "RCC"
    # reset values, §6.3.1 (CR: HSION, HSIRDY, HSITRIM = 16), §6.3.2 PLLCFGR,
    # §6.3.21 CSR (reset flags: PORRSTF, PINRSTF)
    reset = {CR: 0x0000_0083, PLLCFGR: 0x2400_3010, CSR: 0x0E00_0000}

    def read(self, off):
        v = self.get(off)
        if off == CR:
            # §6.3.1: HSIRDY/HSERDY/PLLRDY/PLLI2SRDY follow their ON bits
            # (stabilisation times are not modelled)
            v &= ~((1 << 1) | (1 << 17) | (1 << 25) | (1 << 27))
            for on in (0, 16, 24, 26):
                if v >> on & 1:
                    v |= 1 << (on + 1)
        elif off == CFGR:
            # §6.3.3: SWS (bits 3:2) follows SW (bits 1:0)
            v = v & ~0xC | (v & 3) << 2
        elif off == CSR:
            # §6.3.21: LSIRDY follows LSION
            v = v & ~2 | (v & 1) << 1
        return v

    def write(self, off, value, mask):
        if off == CSR and value & mask & (1 << 24):
            # RMVF clears the reset flags (§6.3.21)
            self.r[CSR] = self.get(CSR) & 0x00FF_FFFF
            return
        super().write(off, value, mask)

    # --- the clock tree (§6.2, figure 12) ---
    def sysclk(self):
        sw = self.get(CFGR) & 3
        if sw == 0:
            return HSI_HZ
        if sw == 1:
            return HSE_HZ
        return self.pll()[0]

    def pll(self):
        """(P output, Q output) from RCC_PLLCFGR (§6.3.2)."""
        c = self.get(PLLCFGR)
        src = HSE_HZ if c >> 22 & 1 else HSI_HZ
        m, n = c & 0x3F, c >> 6 & 0x1FF
        p = 2 * ((c >> 16 & 3) + 1)
        q = c >> 24 & 0xF
        if m == 0 or not self.get(CR) >> 24 & 1:
            return (0, 0)
        vco = src * n // m
        return (vco // p, vco // q if q else 0)

    def hclk(self):
        return self.sysclk() // AHB_DIV.get(self.get(CFGR) >> 4 & 0xF, 1)

    def _apb(self, shift):
        div = APB_DIV.get(self.get(CFGR) >> shift & 7, 1)
        pclk = self.hclk() // div
        # §6.2: timers run at PCLK when the APB prescaler is 1, else at 2 x PCLK
        return pclk, pclk if div == 1 else 2 * pclk

    def apb1(self):
        return self._apb(10)

    def apb2(self):
        return self._apb(13)

    def enabled(self, enr_off, bit):
        return bool(self.get(enr_off) >> bit & 1)


class Pwr(Regs):
    name = "PWR"
    # §5.4.1 PWR_CR: VOS (bits 15:14) resets to scale 2 (0b10); reads back
    reset = {0x00: 0x0000_8000}

    def read(self, off):
        v = self.get(off)
        if off == 0x04:
            # §5.4.2 PWR_CSR.VOSRDY (bit 14): ready once the PLL is on
            # (the scale is applied when the PLL starts)
            v &= ~(1 << 14)
            if self.m.rcc.get(CR) >> 24 & 1:
                v |= 1 << 14
        return v


class Flash(Regs):
    name = "FLASH"
    # §3.8: ACR reads back (LATENCY, PRFTEN, ICEN, DCEN); CR reset LOCK;
    # OPTCR reset 0x0FFF_AAED. No programming or erase is modelled.
    reset = {0x10: 0x8000_0000, 0x14: 0x0FFF_AAED}

    def write(self, off, value, mask):
        if off == 0x00:
            # ICRST/DCRST (bits 11, 12) only act on the caches: read back
            super().write(off, value, mask)
        elif off == 0x0C:
            # SR: EOP/error flags are rc_w1 (§3.8.4)
            self.r[off] = self.get(off) & ~(value & mask)
        elif off == 0x10 and value & mask & ((1 << 16) | (1 << 1) | 1):
            # a program or erase start: not modelled, logged
            self.m.log("FLASH_CR 0x%08x: program/erase not modelled" % value)
            super().write(off, value, mask)
        else:
            super().write(off, value, mask)
