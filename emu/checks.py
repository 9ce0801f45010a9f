"""The checks, each printing one PASS/FAIL line with its figures."""
from periph.timer import CR1, CCR, PSC, ARR, CEN, SR
from periph.gpio import MODER, AFRL, AFRH, PUPDR

BOOT_BOUND = 1_000_000      # instructions (about 10 ms at 96 MHz) to reach the main loop
TICK_TOLERANCE = 1          # handler runs, against the rate over the window


class Report:
    def __init__(self):
        self.failed = 0

    def line(self, ok, name, text):
        self.failed += not ok
        print("%s %-18s %s" % ("PASS" if ok else "FAIL", name, text))
        return ok


def boot(r, m, exp, t_end):
    started = m.iwdg.started_at()
    pets = m.iwdg.pets()
    led = m.gpio["C"]
    led_out = m.led_driven_at
    ok = (not m.faults and started is not None and started <= BOOT_BOUND and led_out is not None
          and led_out <= BOOT_BOUND and len(pets) >= 1)
    gaps = [b - a for a, b in zip([started or 0] + pets, pets)]
    text = ("watchdog started at %s instr (bound %d), %d pets by %d instr (longest gap %.1f ms), "
            "LED PC13 output at %s instr, PC13=%d; faults: %s"
            % (started, BOOT_BOUND, len(pets), t_end, max(gaps, default=0) / exp["sysclk_hz"] * 1e3,
               led_out, led.get(0x14) >> 13 & 1, "; ".join(t for _, t in m.faults) or "none"))
    return r.line(ok, "boot", text)


def registers(r, m, exp):
    bad = []
    for p in exp["pins"]:
        g = m.gpio[p["port"]]
        i = p["index"]
        got = (g.field(MODER, i), g.afr(i) if p["afr"] is not None else None, g.field(PUPDR, i))
        want = (p["moder"], p["afr"], p["pupdr"])
        if got != want:
            bad.append("%s %s: MODER/AFR/PUPDR %s, board.rs %s" % (p["signal"], p["pin"], got, want))
    for q in exp["priorities"]:
        n = m.irqs[q["name"]]
        got = m.ppb.prio[16 + n]
        if got != q["ipr"] or not m.ppb.enabled[n]:
            bad.append("%s (IRQ %d): IPR 0x%02x enabled=%s, board.rs 0x%02x" % (q["name"], n, got, m.ppb.enabled[n], q["ipr"]))
    # nothing else enabled at or above the tick's level: it would delay the
    # tick, or race the state app/cs.rs's BASEPRI section protects
    tick = m.ppb.prio[16 + m.irqs["TIM1_TRG_COM_TIM11"]]
    names = {v: k for k, v in m.irqs.items()}
    allowed = {m.irqs["TIM1_TRG_COM_TIM11"], m.irqs["EXTI15_10"]}
    crowd = [n for n in range(len(m.ppb.enabled)) if m.ppb.enabled[n] and m.ppb.prio[16 + n] <= tick and n not in allowed]
    if crowd:
        bad.append("enabled at the tick's level: %s" % ", ".join(names.get(n, str(n)) for n in crowd))
    sysclk = m.rcc.sysclk()
    if sysclk != exp["sysclk_hz"]:
        bad.append("SYSCLK %d, board.rs %d" % (sysclk, exp["sysclk_hz"]))
    t11 = m.tim["TIM11"]
    rate = t11.clk() / ((t11.get(PSC) + 1) * (t11.get(ARR) + 1))
    if rate != exp["tick_hz"]:
        bad.append("tick %.1f Hz, board.rs %d" % (rate, exp["tick_hz"]))
    if m.vector_mismatch:
        bad.append("handlers not at their SVD vectors: %s" % m.vector_mismatch)
    apb1, apb2 = m.rcc.apb1(), m.rcc.apb2()
    text = ("%d pins, %d priorities, SYSCLK %.0f MHz (APB1 %.0f/%.0f MHz timers, APB2 %.0f/%.0f), tick %.0f Hz"
            % (len(exp["pins"]), len(exp["priorities"]), sysclk / 1e6, apb1[0] / 1e6, apb1[1] / 1e6,
               apb2[0] / 1e6, apb2[1] / 1e6, rate))
    return r.line(not bad, "registers", text + ("; " + "; ".join(bad) if bad else ""))


def tick(r, m, exp, t0, t1, runs0, runs1, upd0, upd1):
    t11 = m.tim["TIM11"]
    rate = t11.clk() / ((t11.get(PSC) + 1) * (t11.get(ARR) + 1))
    secs = (t1 - t0) / m.rcc.sysclk()
    want = rate * secs
    runs, updates = runs1 - runs0, upd1 - upd0
    uif_left = t11.get(SR) & 1
    ok = abs(runs - want) <= TICK_TOLERANCE and runs == updates and m.tick_uif_clears >= runs
    return r.line(ok, "tick", "TIM11 PSC=%d ARR=%d at %.0f MHz -> %.1f Hz; over %.1f ms: %d handler runs (expected %.1f), "
                  "%d update events, UIF cleared in %d runs, UIF now %d"
                  % (t11.get(PSC), t11.get(ARR), t11.clk() / 1e6, rate, secs * 1e3, runs, want, updates,
                     m.tick_uif_clears - m.tick_uif_clears0, uif_left))


def outputs(m, exp):
    """The outputs as the pins see them."""
    t1, t10 = m.tim["TIM1"], m.tim["TIM10"]
    step = t1.oc_out(0) if m.gpio["A"].field(MODER, 8) == 2 else m.gpio["A"].pin_out(8)
    t10_rate = t10.clk() / (t10.get(PSC) + 1)
    stop = exp["esc_stop_us"] * t10_rate / 1e6
    inactive = 1 if not exp["enable_active_high"] else 0
    return {
        "TIM1 CEN": t1.get(CR1) & CEN, "OC1M": t1.oc_mode(0), "STEP(PA8)": step,
        "ESC CCR1": t10.get(CCR[0]), "ESC stop": stop,
        "ENABLE(PB13)": m.gpio["B"].pin_out(13), "ENABLE inactive": inactive,
        "X_STEP(PB4)": m.gpio["B"].pin_out(4),
    }


def safe_now(o):
    """The E-stop interrupt's own work: step output halted, ESC stopped."""
    return o["TIM1 CEN"] == 0 and o["STEP(PA8)"] == 0 and o["ESC CCR1"] == o["ESC stop"]


def safe_all(o):
    return safe_now(o) and o["ENABLE(PB13)"] == o["ENABLE inactive"] and o["X_STEP(PB4)"] == 0


def fmt(o):
    return "TIM1 CEN=%d OC1M=%d STEP=%s, TIM10 CCR1=%d (stop %d), ENABLE=%s (inactive %d), X_STEP=%s" % (
        o["TIM1 CEN"], o["OC1M"], o["STEP(PA8)"], o["ESC CCR1"], o["ESC stop"], o["ENABLE(PB13)"],
        o["ENABLE inactive"], o["X_STEP(PB4)"])


def safety(r, m, name, before, at_return, after, edge_at, handled_at):
    ok = at_return is not None and safe_now(at_return) and safe_all(after) and not m.faults
    lat = "-" if handled_at is None else "%d instr" % (handled_at - edge_at)
    return r.line(ok, name, "before: %s | EXTI15_10 return (%s after the edge): %s | 2 ms later: %s%s"
                  % (fmt(before), lat, fmt(at_return) if at_return else "never ran", fmt(after),
                     "; faults: " + "; ".join(t for _, t in m.faults) if m.faults else ""))


def primask(r, m):
    """Report only: the longest PRIMASK section in thread mode, and the
    longest begun while the tick's interrupt was enabled (the ones that can
    delay it; app/cs.rs keeps logging and embassy off PRIMASK)."""
    mhz = m.rcc.sysclk() / 1e6

    def part(sec):
        length, pc = sec
        where = m.image.func_at(pc) if pc else "-"
        return "%d instructions (%.1f us) from %s (0x%08x)" % (length, length / mhz, where, pc or 0)
    return r.line(True, "irq-off", "longest PRIMASK section in thread mode: %s; with the tick running: %s; "
                  "%d sections" % (part(m.pm_longest), part(m.pm_ticking), m.pm_sections))
