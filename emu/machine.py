"""The emulated STM32F411: unicorn's Cortex-M4 core (Thumb, M-class), the
memory map (RM0383 §2.3: flash 512 KiB at 0x0800_0000, also aliased at 0
with BOOT0 = 0 (§2.4); SRAM 128 KiB at 0x2000_0000), the peripheral bus,
and time.

Time: one emulated instruction is one CPU cycle at the system clock the
firmware configured (96 MHz here, from the RCC model). Instructions are
counted per translated block (a Python block hook adds the block's
instruction count, decoded from its Thumb halfwords), so the count is exact
at block boundaries; an MMIO access sees the time at the start of its
block. Exception entry and return cost no cycles. The run is sliced: it
stops at the first block boundary at or after the next due timer event,
where pending interrupts are taken (exceptions.py)."""
import ctypes

from unicorn import Uc, UcError, UC_ARCH_ARM, UC_MODE_THUMB, UC_MODE_MCLASS, UC_HOOK_BLOCK, \
    UC_HOOK_INTR, UC_HOOK_CODE, UC_HOOK_MEM_INVALID, UC_PROT_READ, UC_PROT_EXEC, UC_PROT_ALL
from unicorn.arm_const import UC_ARM_REG_PC, UC_ARM_REG_SP, UC_ARM_REG_IPSR, UC_ARM_REG_PRIMASK, \
    UC_ARM_REG_R0

from bus import Bus
from exceptions import Exceptions

FLASH, FLASH_SIZE = 0x0800_0000, 512 * 1024
RAM, RAM_SIZE = 0x2000_0000, 128 * 1024
NOP = b"\x00\xbf"
SLICE = 20_000          # longest run between checks for interrupts (instructions)


def insn_count(code, start, size):
    """Thumb instructions in code[start:start+size]: a halfword whose top
    five bits are 0b11101, 0b11110 or 0b11111 starts a 32-bit instruction."""
    n, i = 0, start
    while i < start + size:
        hw = code[i] | code[i + 1] << 8
        i += 4 if hw >> 11 in (0x1D, 0x1E, 0x1F) else 2
        n += 1
    return n


class Machine:
    def __init__(self, image, verbose=False):
        self.image, self.verbose = image, verbose
        self.uc = uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
        self.flash = ctypes.create_string_buffer(b"\xff" * FLASH_SIZE, FLASH_SIZE)  # erased flash
        for addr, data in image.segments:
            if not FLASH <= addr < FLASH + FLASH_SIZE:
                raise SystemExit("emu: PT_LOAD at 0x%x is outside flash" % addr)
            ctypes.memmove(ctypes.addressof(self.flash) + addr - FLASH, data, len(data))
        # WFE and SEV are NOPs here (ARMv7-M ARM B1.5.18 allows WFE to be a
        # NOP; unicorn lacks both): patched at the addresses llvm-objdump found
        for a in image.insns["wfe"] + image.insns["sev"] + image.insns["wfi"]:
            ctypes.memmove(ctypes.addressof(self.flash) + a - FLASH, NOP, 2)
        self.code = self.flash.raw
        ptr = ctypes.addressof(self.flash)
        uc.mem_map_ptr(FLASH, FLASH_SIZE, UC_PROT_READ | UC_PROT_EXEC, ptr)
        uc.mem_map_ptr(0, FLASH_SIZE, UC_PROT_READ | UC_PROT_EXEC, ptr)
        uc.mem_map(RAM, RAM_SIZE, UC_PROT_ALL)
        self.bus = Bus(self)
        for base, size in ((0x4000_0000, 0x8_0000), (0x5000_0000, 0x4_0000), (0xE000_0000, 0x10_0000),
                           (0x1FFF_0000, 0x1_0000)):
            uc.mmio_map(base, size, self._rd, base, self._wr, base)
        self.now = 0                 # instructions executed (= cycles)
        self.blk_count = 0           # count at the start of the current block
        self.deadline = 0
        self._cur_addr = FLASH
        self.blocks = {}
        self.faults = []
        self.events = []             # (cycle, text) of notable things
        self.logs = []
        self.reset_requested = False
        self.on_enter = self.on_return = None   # callbacks (exception number)
        self.active = []             # active exception numbers, outermost first
        self.timed = []              # models with advance/next_event
        self.exc = Exceptions(self)
        self.primask_hooks()
        uc.hook_add(UC_HOOK_BLOCK, self._block)
        uc.hook_add(UC_HOOK_INTR, self._intr)
        uc.hook_add(UC_HOOK_MEM_INVALID, self._invalid)

    # --- logging ---
    def log(self, text):
        self.logs.append((self.now, text))
        if self.verbose:
            print("  [%d] %s" % (self.now, text))

    def log_event(self, text):
        self.events.append((self.now, text))
        self.log(text)

    # --- time ---
    def _block(self, uc, addr, size, _):
        if self.now >= self.deadline:
            # stops before this block runs (tested); the PC unicorn reports
            # then can be the previous block's start, so resume from here
            self.resume = addr
            uc.emu_stop()
            return
        self._cur_addr = addr
        n = self.blocks.get((addr, size))
        if n is None:
            code = self.code if FLASH <= addr < FLASH + FLASH_SIZE else None
            n = insn_count(code, addr - FLASH, size) if code else insn_count(bytes(uc.mem_read(addr, size)), 0, size)
            self.blocks[(addr, size)] = n
        self.blk_count = self.now
        self.now += n

    def now_exact(self):
        """The time an MMIO access sees: the start of its block."""
        return self.blk_count

    def request_stop(self):
        self.deadline = 0

    def sync(self):
        t = self.now_exact()
        for m in self.timed:
            m.advance(t)

    def after_write(self):
        self.exc.update_lines()
        if self.exc.deliverable():
            self.request_stop()

    # --- registers ---
    def pc(self):
        return self.uc.reg_read(UC_ARM_REG_PC)

    def ipsr(self):
        return self.uc.reg_read(UC_ARM_REG_IPSR) & 0x1FF

    def _rd(self, uc, off, size, base):
        return self.bus.read(base + off, size)

    def _wr(self, uc, off, size, value, base):
        self.bus.write(base + off, size, value)

    # --- faults ---
    def fault(self, text):
        self.faults.append((self.now, text))
        self.log("FAULT: " + text)
        self.uc.emu_stop()

    def _intr(self, uc, intno, _):
        if intno == 8:               # EXCP_EXCEPTION_EXIT: PC loaded with EXC_RETURN
            self.exc.exit(self.pc() | 1)
            return
        kind = {1: "UsageFault (undefined instruction)", 3: "prefetch abort", 4: "data abort",
                2: "SVC", 7: "BKPT"}.get(intno, "exception %d" % intno)
        self.fault("%s at 0x%08x in %s" % (kind, self.pc(), self.image.func_at(self.pc())))

    def _invalid(self, uc, access, addr, size, value, _):
        self.fault("bus fault: access %d to unmapped 0x%08x at pc 0x%08x (%s)"
                   % (access, addr, self.pc(), self.image.func_at(self.pc())))
        return False

    def trap(self, addr, text):
        """Stop with a fault if code at addr runs (the fault handlers)."""
        self.uc.hook_add(UC_HOOK_CODE, lambda uc, a, s, _: self.fault(text), None, addr, addr)

    # --- PRIMASK (interrupts-off sections) ---
    def primask_hooks(self):
        self.pm_since = None          # (cycle, pc, tick on) where PRIMASK went to 1 in thread mode
        self.pm_longest = (0, None)   # (instructions, pc)
        self.pm_ticking = (0, None)   # the same, for sections begun with the tick's IRQ enabled
        self.pm_sections = 0
        for a in self.image.insns["cpsid"]:
            self.uc.hook_add(UC_HOOK_CODE, self._pm, 1, a, a)
        for a in self.image.insns["cpsie"]:
            self.uc.hook_add(UC_HOOK_CODE, self._pm, 0, a, a)
        for a in self.image.insns["msr_primask"]:
            self.uc.hook_add(UC_HOOK_CODE, self._pm, None, a, a)

    def _pm(self, uc, addr, size, value):
        if value is None:             # msr primask, rN: the value is in rN
            hw = self.code[addr - FLASH] | self.code[addr - FLASH + 1] << 8
            value = uc.reg_read(UC_ARM_REG_R0 + (hw & 0xF)) & 1
        t = self.blk_count + insn_count(self.code, self._cur_addr - FLASH, addr - self._cur_addr)
        if self.ipsr():
            return                    # only thread-mode sections are measured
        if value and self.pm_since is None and not uc.reg_read(UC_ARM_REG_PRIMASK):
            self.pm_since = (t, addr, self.exc.nvic.enabled[self.irqs["TIM1_TRG_COM_TIM11"]])
        elif not value and self.pm_since is not None:
            length = t - self.pm_since[0]
            self.pm_sections += 1
            if length > self.pm_longest[0]:
                self.pm_longest = (length, self.pm_since[1])
            if self.pm_since[2] and length > self.pm_ticking[0]:
                self.pm_ticking = (length, self.pm_since[1])
            self.pm_since = None
            if self.exc.deliverable(primask=0):
                self.request_stop()   # taken as soon as this block ends

    # --- running ---
    def boot(self):
        sp, rv = self.image.vectors[0], self.image.vectors[1]
        self.uc.reg_write(UC_ARM_REG_SP, sp)
        self.uc.reg_write(UC_ARM_REG_PC, rv)

    def run(self, cycles):
        end = self.now + cycles
        while self.now < end and not self.faults:
            self.sync()
            self.exc.update_lines()
            self.exc.take()
            nxt = [t for t in (m.next_event(self.now) for m in self.timed) if t is not None]
            self.deadline = min([end, self.now + SLICE] + nxt)
            self.blk_count = self.now
            self.resume = None
            try:
                self.uc.emu_start(self.pc() | 1, 0xFFFF_FFFF)
            except UcError as e:
                if not self.faults:
                    self.fault("unicorn: %s at 0x%08x (%s)" % (e, self.pc(), self.image.func_at(self.pc())))
            if self.resume is not None and not self.faults:
                self.uc.reg_write(UC_ARM_REG_PC, self.resume | 1)
        self.sync()
