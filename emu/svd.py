"""Interrupt numbers and peripheral base addresses of the STM32F411CE,
from ST's SVD as stm32-metapac generates it (the version Cargo.lock pins,
in the cargo registry): nothing about them is typed in by hand here."""
import glob
import os
import re


def metapac_pac(repo):
    lock = open(os.path.join(repo, "Cargo.lock")).read()
    m = re.search(r'name = "stm32-metapac"\nversion = "([^"]+)"', lock)
    if not m:
        raise SystemExit("emu: stm32-metapac is not in Cargo.lock")
    home = os.environ.get("CARGO_HOME", os.path.expanduser("~/.cargo"))
    hits = glob.glob(os.path.join(home, "registry/src/*/stm32-metapac-%s/src/chips/stm32f411ce/pac.rs" % m.group(1)))
    if not hits:
        raise SystemExit("emu: stm32-metapac %s not in the cargo registry (cargo fetch)" % m.group(1))
    return open(hits[0]).read()


def load(repo):
    """(interrupt name -> number, peripheral name -> base address)."""
    pac = metapac_pac(repo)
    irqs = {name: int(num) for name, num in re.findall(r"^\s+(\w+) = (\d+),$", pac, re.M)}
    bases = {name: int(addr.replace("_", ""), 16)
             for name, addr in re.findall(r"pub const (\w+): [\w:]+ = unsafe \{ [\w:]+::from_ptr\((0x[0-9a-f_]+)usize", pac)}
    return irqs, bases


def check_vectors(image, irqs):
    """Every interrupt handler the firmware defines sits at its number's
    vector: ties the SVD's numbers to this image."""
    bad = []
    for name, n in irqs.items():
        addr = image.symbols.get(name)
        if addr is not None and 16 + n < len(image.vectors) and image.vectors[16 + n] & ~1 != addr:
            bad.append(name)
    return bad
