"""polyturn's firmware image on an emulated STM32F411 (.ci/emu).

usage: python emu/main.py ELF EXPECTED.json [-v]

Scenarios (each from reset, flash erased, so default settings):
  1. boot and run 160 ms with the E-stop closed (PB14 driven low) and no
     drive alarm (PB15 floating, pulled up): boot, registers, tick;
     then the E-stop opens (PB14 floats, its pull-up takes it high).
  2. boot and run 60 ms, then the drive alarm pulls PB15 low.
Time: 1 instruction = 1 CPU cycle at the clock the firmware configured."""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from elfimage import Image  # noqa: E402
import checks  # noqa: E402
import soc  # noqa: E402
from periph.timer import SR, CCR  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MS = 96_000   # instructions per ms at 96 MHz; the checks use the modelled SYSCLK


def machine(image, verbose):
    m = soc.build(image, REPO, verbose)
    tick_exc = 16 + m.irqs["TIM1_TRG_COM_TIM11"]
    exti_exc = 16 + m.irqs["EXTI15_10"]
    m.tick_uif_clears = m.tick_uif_clears0 = 0
    m.exti_return = m.exti_entered = None
    m.after_tick = None

    def on_return(exc):
        if exc == tick_exc:
            if not m.tim["TIM11"].get(SR) & 1:
                m.tick_uif_clears += 1
            if m.after_tick:
                m.after_tick()
        elif exc == exti_exc and m.exti_return is None:
            m.exti_return = checks.outputs(m, m.expected)

    def on_enter(exc):
        if exc == exti_exc and m.exti_entered is None:
            m.exti_entered = m.now
    m.on_return, m.on_enter = on_return, on_enter
    m.tick_exc = tick_exc
    return m


def trip(m, drive, level):
    """Fires the input change right after a tick returns, having set the
    ESC to a running pulse (1.5 x the stop pulse, as a running BLDC would
    have it) so the E-stop interrupt's own work is visible before the next
    tick would redo it."""
    t10 = m.tim["TIM10"]

    def fire():
        m.after_tick = None
        stop = checks.outputs(m, m.expected)["ESC stop"]
        t10.write(CCR[0], int(stop * 1.5), 0xFFFF)
        m.before = checks.outputs(m, m.expected)
        m.edge_at = m.now
        m.gpio["B"].drive(drive, level)
        m.after_write()
    m.after_tick = fire


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("-")]
    verbose = "-v" in sys.argv
    wall0 = time.time()
    image = Image(args[0])
    exp = json.load(open(args[1]))
    r = checks.Report()
    total = 0

    # --- scenario 1: boot, registers, tick, E-stop ---
    m = machine(image, verbose)
    m.expected = exp
    m.gpio["B"].drive(14, 0)                 # E-stop closed to GND
    m.run(60 * MS)
    runs0, upd0, t0 = m.exc.entries.get(m.tick_exc, 0), m.tim["TIM11"].updates, m.now
    m.tick_uif_clears0 = m.tick_uif_clears
    m.run(100 * MS)
    runs1, upd1, t1 = m.exc.entries.get(m.tick_exc, 0), m.tim["TIM11"].updates, m.now
    m.led_driven_at = m.gpio["C"].output_since.get(13)
    checks.boot(r, m, exp, m.now)
    checks.registers(r, m, exp)
    checks.tick(r, m, exp, t0, t1, runs0, runs1, upd0, upd1)
    trip(m, 14, None)                        # the contact opens: PB14 floats high
    m.run(2 * MS)
    checks.safety(r, m, "safety-estop", m.before, m.exti_return, checks.outputs(m, exp), m.edge_at,
                  m.exti_entered)
    checks.primask(r, m)
    total += m.now
    unmapped = dict(m.bus.unmapped)

    # --- scenario 2: drive alarm from a fresh boot ---
    m = machine(image, verbose)
    m.expected = exp
    m.gpio["B"].drive(14, 0)
    m.run(60 * MS)
    trip(m, 15, 0)                           # the drive pulls ALARM to GND
    m.run(2 * MS)
    checks.safety(r, m, "safety-alarm", m.before, m.exti_return, checks.outputs(m, exp), m.edge_at,
                  m.exti_entered)
    total += m.now
    unmapped.update(m.bus.unmapped)

    for addr, (kind, where) in sorted(unmapped.items()):
        print("note: unmodelled %s at 0x%08x (first from %s), read as 0" % (kind, addr, where))
    print("emulated %d instructions (%.1f ms of MCU time) in %.1f s wall; %d check(s) failed"
          % (total, total / exp["sysclk_hz"] * 1e3, time.time() - wall0, r.failed))
    return 1 if r.failed else 0


if __name__ == "__main__":
    sys.exit(main())
