#!/usr/bin/env python3
"""Where the control tick's instructions go: a profile by stage.

Runs the QEMU tick image (`.ci/qemu`'s, the same build) with one
instruction per translation block and logs every instruction executed in
the functions reachable from `polyturn_tick`. It keeps the main loop's
ticks 6 001 to 20 000, all synchronised at 600 rpm (the lathe reaches
speed at tick 5 000 and holds it to 20 000), and gives each executed
instruction to the stage `Controller::control` called (its inlined callee,
from the debug line tables: llvm-symbolizer), or to the out-of-line
function it lies in. The figures are instructions a tick, averaged; the
total is the tick's own average less `polyturn_tick`'s call and the meter.

    python3 firmware/qemu-tick/profile.py [--lines]

`--lines` gives each instruction to its innermost line of the project's
own code instead (core's `min`, `max` and loops to the line calling them).

Needs qemu-system-arm (as .ci/qemu), rustup's llvm-tools (llvm-objdump)
and llvm-symbolizer (apt: llvm). A development tool: CI does not run it.
"""
import collections
import glob
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
ELF = os.path.join(ROOT, "target/thumbv7em-none-eabihf/fw/polyturn-qemu-tick")
# the main loop's ticks kept: synchronised at full speed (mcu.rs's ramp)
FIRST, LAST = 6_001, 20_000
ROOT_FN = "polyturn_tick"


def tool(name):
    sysroot = subprocess.check_output(["rustc", "--print", "sysroot"], text=True).strip()
    found = glob.glob(os.path.join(sysroot, "**", name), recursive=True) or [shutil.which(name)]
    if not found or not found[0]:
        sys.exit(f"error: {name} not found (rustup component add llvm-tools; apt install llvm)")
    return found[0]


def functions(dis):
    """name -> (first, last) address, and name -> names it branches to."""
    spans, calls, fn = {}, collections.defaultdict(set), None
    for line in dis.splitlines():
        head = re.match(r"^([0-9a-f]+) <(.*)>:$", line)
        if head:
            fn = head.group(2)
            spans[fn] = [int(head.group(1), 16)] * 2
            continue
        ins = re.match(r"^\s+([0-9a-f]+):\s+(\S+)", line)
        if fn and ins:
            spans[fn][1] = int(ins.group(1), 16)
            target = re.search(r"\t(?:bl|b|blx)\w*(?:\.w|\.n)?\t.*<([^>+]+)", line)
            if target:
                calls[fn].add(target.group(1))
    return spans, calls


def reachable(calls, root):
    seen, todo = {root}, [root]
    while todo:
        for g in calls[todo.pop()]:
            if g not in seen:
                seen.add(g)
                todo.append(g)
    return seen


def trace(ranges):
    """Executed instruction addresses -> times, over the kept ticks."""
    flt = ",".join(f"0x{a:x}..0x{b + 1:x}" for a, b in ranges)
    cmd = ["qemu-system-arm", "-M", "netduinoplus2", "-icount", "shift=0", "-nographic",
           "-monitor", "none", "-semihosting-config", "enable=on,target=native",
           "-kernel", ELF, "-singlestep", "-d", "exec,nochain", "-dfilter", flt]
    q = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    entry, ticks, seen = ranges[0][0], 0, collections.Counter()
    for line in q.stderr:
        if not line.startswith("Trace"):
            continue
        pc = int(line.split("/")[1], 16)
        ticks += pc == entry
        if ticks > LAST:
            break
        if ticks >= FIRST:
            seen[pc] += 1
    q.kill()
    return seen, min(ticks, LAST) - FIRST + 1


def stages(seen):
    """Instructions by the stage `Controller::control` called, or out of line."""
    sym = subprocess.run([tool("llvm-symbolizer"), f"--obj={ELF}", "--inlining", "--demangle"],
                         input="".join(f"0x{a:x}\n" for a in seen), capture_output=True, text=True)
    by = collections.Counter()
    for addr, block in zip(seen, sym.stdout.strip().split("\n\n")):
        lines = block.split("\n")
        names = [re.sub(r"::h[0-9a-f]{16}$", "", n) for n in lines[0::2]]
        # innermost first: the frame inside `Controller::control` is the stage
        at = next((i for i, n in enumerate(names) if n.endswith("Controller::control")), None)
        stage = names[-1] + " (out of line)" if at is None else names[max(at - 1, 0)]
        # (an impl block's and a closure's mangled names, shortened)
        stage = re.sub(r"_\$LT\$impl\$u20\$.*?\$GT\$::", "", stage.replace("polyturn_sync::", ""))
        by[re.sub(r"::_\$u7b\$\$u7b\$closure\$u7d\$\$u7d\$", " (a closure)", stage)] += seen[addr]
    return by


def lines(seen):
    """Instructions by the innermost source line (`--lines`)."""
    sym = subprocess.run([tool("llvm-symbolizer"), f"--obj={ELF}", "--inlining", "--demangle"],
                         input="".join(f"0x{a:x}\n" for a in seen), capture_output=True, text=True)
    by = collections.Counter()
    for addr, block in zip(seen, sym.stdout.strip().split("\n\n")):
        # the innermost frame in the project's own code (not core's min/max)
        at = [a for a in block.split("\n")[1::2] if "/firmware/" in a] or block.split("\n")[1:2]
        by[re.sub(r"^.*?/(firmware|host-sim)/", r"\1/", at[0])] += seen[addr]
    return by


def main():
    subprocess.check_call(["cargo", "build", "-q", "-p", "polyturn-qemu-tick",
                           "--target", "thumbv7em-none-eabihf", "--profile", "fw"], cwd=ROOT)
    dis = subprocess.check_output([tool("llvm-objdump"), "-d", "--no-show-raw-insn", ELF], text=True)
    spans, calls = functions(dis)
    tick = next((n for n in spans if "Controller7control" in n), None)
    if tick is None:
        sys.exit("error: Controller::control is not out of line in the image: nothing to count its entries by")
    # the tick's entry first: it counts the ticks
    names = [tick] + sorted(reachable(calls, ROOT_FN) - {tick, ROOT_FN})
    seen, n = trace([tuple(spans[f]) for f in names if f in spans])
    total = 0
    for stage, k in (lines if "--lines" in sys.argv else stages)(seen).most_common():
        total += k
        print(f"{k / n:7.1f}  {stage}")
    print(f"{total / n:7.1f}  instructions a tick in all, over {n} ticks synchronised at 600 rpm")


if __name__ == "__main__":
    main()
