"""The firmware image: loadable segments, symbols, vector table and the
addresses of the instructions the harness treats specially, all read from
the ELF on every run (nothing about the code is hard-coded here)."""
import bisect
import glob
import os
import re
import subprocess

from elftools.elf.elffile import ELFFile

FLASH_BASE = 0x0800_0000


def find_objdump():
    sysroot = subprocess.run(["rustc", "--print", "sysroot"], capture_output=True, text=True,
                             check=True).stdout.strip()
    hits = sorted(glob.glob(os.path.join(sysroot, "lib/rustlib/*/bin/llvm-objdump")))
    if not hits:
        raise SystemExit("emu: no llvm-objdump under the rust sysroot (rustup component add llvm-tools)")
    return hits[0]


class Image:
    def __init__(self, path):
        self.path = path
        with open(path, "rb") as f:
            elf = ELFFile(f)
            # PT_LOAD segments at their load address (LMA): .data's initial
            # values sit in flash and cortex-m-rt copies them at reset
            self.segments = [(seg["p_paddr"], seg.data()[: seg["p_filesz"]])
                             for seg in elf.iter_segments()
                             if seg["p_type"] == "PT_LOAD" and seg["p_filesz"] > 0]
            self.symbols = {}
            funcs = []
            for sym in elf.get_section_by_name(".symtab").iter_symbols():
                if not sym.name or sym["st_info"]["type"] not in ("STT_FUNC", "STT_OBJECT", "STT_NOTYPE"):
                    continue
                addr = sym["st_value"]
                if sym["st_info"]["type"] == "STT_FUNC":
                    addr &= ~1
                    funcs.append((addr, sym["st_size"], sym.name))
                self.symbols.setdefault(sym.name, addr)
            vt = elf.get_section_by_name(".vector_table")
            self.vector_base = vt["sh_addr"]
            raw = vt.data()
            self.vectors = [int.from_bytes(raw[i:i + 4], "little") for i in range(0, len(raw), 4)]
        funcs.sort()
        self._func_addrs = [a for a, _, _ in funcs]
        self._funcs = funcs
        self.insns = self._scan()

    def _scan(self):
        """Addresses of wfe/sev/udf/cpsid/cpsie/msr primask, from llvm-objdump."""
        out = subprocess.run([find_objdump(), "-d", "--no-show-raw-insn", self.path],
                             capture_output=True, text=True, check=True).stdout
        found = {k: [] for k in ("wfe", "sev", "wfi", "udf", "cpsid", "cpsie", "msr_primask")}
        line_re = re.compile(r"^\s*([0-9a-f]+):\s+([a-z.]+)\s*(.*)$")
        for line in out.splitlines():
            m = line_re.match(line)
            if not m:
                continue
            addr, op, args = int(m.group(1), 16), m.group(2), m.group(3)
            if op in ("wfe", "sev", "wfi", "udf"):
                found[op].append(addr)
            elif op in ("cpsid", "cpsie") and args.strip().startswith("i"):
                found[op].append(addr)
            elif op == "msr" and args.lower().startswith("primask"):
                found["msr_primask"].append(addr)
        return found

    def func_at(self, addr):
        """Name of the function containing addr (or the nearest before it)."""
        i = bisect.bisect_right(self._func_addrs, addr & ~1) - 1
        if i < 0:
            return "?"
        a, size, name = self._funcs[i]
        return name if size == 0 or addr < a + size else "%s+0x%x" % (name, addr - a)
