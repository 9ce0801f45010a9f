"""The STM32F411CE as the firmware sees it: every model at its SVD base
address and every interrupt line at its SVD number."""
from machine import Machine
from ppb import Ppb
from periph.rcc import Rcc, Pwr, Flash
from periph.gpio import Gpio, Syscfg, Exti
from periph.timer import Timer
from periph.dma import Dma, tim1_up_to_dma2_s5
from periph.iwdg import Iwdg
from periph.usb import Usb
import svd

# timers: name -> (APB bus, counter bits, channels) from RM0383 §12-§14
TIMERS = {"TIM1": (2, 16, 4), "TIM2": (1, 32, 4), "TIM3": (1, 16, 4), "TIM4": (1, 16, 4),
          "TIM5": (1, 32, 4), "TIM9": (2, 16, 2), "TIM10": (2, 16, 1), "TIM11": (2, 16, 1)}


def build(image, repo, verbose=False):
    irqs, bases = svd.load(repo)
    m = Machine(image, verbose)
    m.irqs = irqs
    m.vector_mismatch = svd.check_vectors(image, irqs)
    b = m.bus
    m.ppb = b.add(Ppb(m, 0xE000_0000))
    m.rcc = b.add(Rcc(m, bases["RCC"]))
    b.add(Pwr(m, bases["PWR"]))
    m.flashif = b.add(Flash(m, bases["FLASH"]))
    m.syscfg = b.add(Syscfg(m, bases["SYSCFG"]))
    m.exti = b.add(Exti(m, bases["EXTI"]))
    m.gpio = {p: b.add(Gpio(m, bases["GPIO" + p], p)) for p in "ABC"}
    m.tim = {}
    for name, (apb, bits, ch) in TIMERS.items():
        t = m.tim[name] = b.add(Timer(m, bases[name], name, apb, bits, ch))
        m.timed.append(t)
    m.dma2 = b.add(Dma(m, bases["DMA2"], "DMA2"))
    b.add(Dma(m, bases["DMA1"], "DMA1"))
    m.tim["TIM1"].dma = tim1_up_to_dma2_s5(m)
    m.iwdg = b.add(Iwdg(m, bases["IWDG"]))
    m.usb = b.add(Usb(m, bases["USB_OTG_FS"]))
    t = m.tim
    line = m.exc.add_line
    # shared vectors (RM0383 §10.2 table 37): TIM1's update with TIM10,
    # its trigger/commutation with TIM11, its break with TIM9
    line(irqs["TIM1_UP_TIM10"], lambda: t["TIM1"].irq_level(0x01) or t["TIM10"].irq_level())
    line(irqs["TIM1_TRG_COM_TIM11"], lambda: t["TIM1"].irq_level(0x60) or t["TIM11"].irq_level())
    line(irqs["TIM1_BRK_TIM9"], lambda: t["TIM1"].irq_level(0x80) or t["TIM9"].irq_level())
    line(irqs["TIM1_CC"], lambda: t["TIM1"].irq_level(0x1E))
    for name in ("TIM2", "TIM3", "TIM4", "TIM5"):
        line(irqs[name], t[name].irq_level)
    # EXTI lines 0-4 have their own vectors, 5-9 and 10-15 share (§10.2.5)
    for i in range(5):
        line(irqs["EXTI%d" % i], lambda i=i: m.exti.line_pending(i, i))
    line(irqs["EXTI9_5"], lambda: m.exti.line_pending(5, 9))
    line(irqs["EXTI15_10"], lambda: m.exti.line_pending(10, 15))
    line(irqs["OTG_FS"], m.usb.irq_level)
    # the fault handlers: reaching one is a failure
    for n, what in ((3, "HardFault"), (4, "MemManage"), (5, "BusFault"), (6, "UsageFault")):
        vec = image.vectors[n] & ~1
        m.trap(vec, "%s handler reached (%s)" % (what, image.func_at(vec)))
    for a in image.insns["udf"]:
        m.trap(a, "udf at 0x%08x in %s" % (a, image.func_at(a)))
    m.boot()
    return m
