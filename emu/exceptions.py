"""Exception entry and return, and the NVIC's choice of what to take
(PM0214 §2.3 exception model, §4.3 NVIC). unicorn's M-class core has no
NVIC: it only reports a load of EXC_RETURN into the PC (QEMU's
EXCP_EXCEPTION_EXIT); everything else is done here.

- Priorities: 8-bit fields, top 4 bits implemented (§4.3.7); pre-emption
  by group priority under AIRCR.PRIGROUP (§2.3.6), only when strictly
  higher than the execution priority (the lowest value among active
  exceptions, PRIMASK boosting it to 0, BASEPRI to its value: §2.1.3).
  Ties among pending exceptions go to the lowest exception number.
- Level-sensitive peripheral lines (§4.3.9): a line that is asserted and
  not active sets its pending bit; it is re-pended after return if still
  asserted.
- Entry (§2.3.7): 8-word frame R0-R3, R12, LR, return address, xPSR
  (bit 9 records a 4-byte alignment of SP, CCR.STKALIGN = 1); with
  CONTROL.FPCA an extended frame (+S0-S15, FPSCR, reserved) and EXC_RETURN
  bit 4 clear. LR = EXC_RETURN, IPSR = exception number, PC from the vector
  table at VTOR (0 aliases flash).
- Return (§2.3.7 "exception return"): unstacks the frame EXC_RETURN names
  and restores IPSR from the stacked xPSR."""
from unicorn.arm_const import UC_ARM_REG_SP, UC_ARM_REG_MSP, UC_ARM_REG_PC, UC_ARM_REG_LR, \
    UC_ARM_REG_XPSR, UC_ARM_REG_PRIMASK, UC_ARM_REG_BASEPRI, UC_ARM_REG_CONTROL, UC_ARM_REG_R0, \
    UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3, UC_ARM_REG_R12, UC_ARM_REG_S0, UC_ARM_REG_FPSCR

FRAME = [UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3, UC_ARM_REG_R12, UC_ARM_REG_LR]


class Exceptions:
    def __init__(self, machine):
        self.m = machine
        self.lines = []          # (irq, callable -> asserted)
        self.entries = {}        # exception number -> times taken
        self.returns = 0

    def add_line(self, irq, fn):
        self.lines.append((irq, fn))

    @property
    def nvic(self):
        return self.m.ppb

    def update_lines(self):
        for irq, fn in self.lines:
            if 16 + irq not in self.m.active and fn():
                self.nvic.pending.add(16 + irq)

    def exec_priority(self, primask=None):
        uc, nv = self.m.uc, self.nvic
        p = min([nv.group(nv.prio[e]) for e in self.m.active] + [256])
        if (uc.reg_read(UC_ARM_REG_PRIMASK) if primask is None else primask) & 1:
            p = min(p, 0)
        bp = uc.reg_read(UC_ARM_REG_BASEPRI) & 0xF0
        if bp:
            p = min(p, nv.group(bp))
        return p

    def best(self):
        nv = self.nvic
        cands = [e for e in nv.pending if e < 16 or nv.enabled[e - 16]]
        return min(cands, key=lambda e: (nv.prio[e], e), default=None)

    def deliverable(self, primask=None):
        e = self.best()
        return e is not None and self.nvic.group(self.nvic.prio[e]) < self.exec_priority(primask)

    def take(self):
        while self.deliverable():
            self.enter(self.best())

    def enter(self, exc):
        uc, m = self.m.uc, self.m
        control = uc.reg_read(UC_ARM_REG_CONTROL)
        if control & 2 and not m.active:
            m.fault("thread mode on PSP: not modelled")
            return
        fp = bool(control & 4)
        sp = uc.reg_read(UC_ARM_REG_SP)
        xpsr = uc.reg_read(UC_ARM_REG_XPSR) | 1 << 24
        words = [uc.reg_read(r) for r in FRAME] + [uc.reg_read(UC_ARM_REG_PC), 0]
        if fp:
            words += [uc.reg_read(UC_ARM_REG_S0 + i) for i in range(16)]
            words += [uc.reg_read(UC_ARM_REG_FPSCR), 0]
        size = 4 * len(words)
        align = (sp - size) & 4
        if align:
            xpsr |= 1 << 9
        words[7] = xpsr
        sp = sp - size - align
        uc.mem_write(sp, b"".join((w & 0xFFFF_FFFF).to_bytes(4, "little") for w in words))
        uc.reg_write(UC_ARM_REG_SP, sp)
        exc_return = 0xFFFF_FFF1 if m.active else 0xFFFF_FFF9
        if fp:
            exc_return &= ~0x10
            uc.reg_write(UC_ARM_REG_CONTROL, control & ~4)
        self.nvic.pending.discard(exc)
        m.active.append(exc)
        self.entries[exc] = self.entries.get(exc, 0) + 1
        uc.reg_write(UC_ARM_REG_LR, exc_return)
        uc.reg_write(UC_ARM_REG_XPSR, (xpsr & ~0x1FF & ~(1 << 9) & ~0x0600_FC00) | exc)
        if m.on_enter:
            m.on_enter(exc)
        vtor = self.nvic.get(0xED08)
        vec = int.from_bytes(uc.mem_read(vtor + 4 * exc, 4), "little")
        uc.reg_write(UC_ARM_REG_PC, vec | 1)

    def exit(self, exc_return):
        uc, m = self.m.uc, self.m
        if not m.active or exc_return & 0xF not in (1, 9, 0xD):
            m.fault("bad EXC_RETURN 0x%08x" % exc_return)
            return
        if exc_return & 0xF == 0xD:
            m.fault("return to PSP: not modelled")
            return
        done = m.active.pop()
        sp = uc.reg_read(UC_ARM_REG_MSP)
        n = 8 if exc_return & 0x10 else 26
        raw = uc.mem_read(sp, 4 * n)
        w = [int.from_bytes(raw[4 * i:4 * i + 4], "little") for i in range(n)]
        for r, v in zip(FRAME, w):
            uc.reg_write(r, v)
        if n == 26:
            for i in range(16):
                uc.reg_write(UC_ARM_REG_S0 + i, w[8 + i])
            uc.reg_write(UC_ARM_REG_FPSCR, w[24])
            uc.reg_write(UC_ARM_REG_CONTROL, uc.reg_read(UC_ARM_REG_CONTROL) | 4)
        xpsr = w[7]
        uc.reg_write(UC_ARM_REG_SP, sp + 4 * n + (4 if xpsr >> 9 & 1 else 0))
        uc.reg_write(UC_ARM_REG_XPSR, xpsr & ~(1 << 9))
        back = xpsr & 0x1FF
        if back != (m.active[-1] if m.active else 0):
            m.fault("return from %d lands in IPSR %d, active %s" % (done, back, m.active))
            return
        uc.reg_write(UC_ARM_REG_PC, w[6] | 1)
        self.returns += 1
        if m.on_return:
            m.on_return(done)
        self.update_lines()
        if self.deliverable():
            m.request_stop()    # taken at the next block boundary (tail-chain)
