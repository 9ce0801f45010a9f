#!/usr/bin/env python3
"""Where a handler's cycles go, by source line: the emulator's per-block
profile (POLYTURN_EMU_PROFILE=DIR writes DIR/tick.blocks and plan.blocks:
address, model cycles, bound cycles) spread over each block's instructions
and given to the source line llvm-objdump -l names for each.
usage: python3 emu/tools/lines.py ELF DIR/tick.blocks [N]"""
import re, subprocess, sys, glob, os
from collections import defaultdict

elf, blocks = sys.argv[1], sys.argv[2]
top = int(sys.argv[3]) if len(sys.argv) > 3 else 40
objdump = glob.glob(os.path.join(subprocess.check_output(["rustc", "--print", "sysroot"], text=True).strip(),
                                 "lib/rustlib/*/bin/llvm-objdump"))[0]
text = subprocess.check_output([objdump, "-d", "-l", "--no-show-raw-insn", elf], text=True)
line_of, order, cur = {}, [], "?"
for l in text.splitlines():
    if l.startswith("; /"):
        cur = l[2:]
        continue
    m = re.match(r"^\s*([0-9a-f]+):\s", l)
    if m:
        a = int(m.group(1), 16)
        line_of[a] = cur
        order.append(a)
order.sort()
import bisect
cost = defaultdict(lambda: [0, 0])
for b in open(blocks):
    a, model, bound = b.split()
    a, model, bound = int(a, 16), int(model), int(bound)
    i = bisect.bisect_left(order, a)
    # the block's instructions: up to the next block boundary is unknown here,
    # so give the whole block to its first instruction's line
    cost[line_of.get(a, "?")][0] += model
    cost[line_of.get(a, "?")][1] += bound
tot = sum(c[1] for c in cost.values())
for k, (m, b) in sorted(cost.items(), key=lambda kv: -kv[1][1])[:top]:
    print(f"{b:>12} {100*b/tot:5.1f}%  {k.replace('/work/main/', '')}")
