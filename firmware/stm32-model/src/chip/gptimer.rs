//! A general-purpose timer as the emulator's event-driven bus sees it: TIM3, TIM4,
//! TIM5 (RM0383 §13) and TIM10 (§14). The counter counts up at CK_CNT = CK_INT /
//! (PSC + 1) (§13.3.1) with CEN set and no slave mode; in encoder mode
//! (SMS = 001..011, §13.3.12) it counts what [`GpTimer::count_by`] is given. At each
//! overflow an update event loads the shadow registers (PSC, ARR and CCRx from what
//! was written: with ARPE or OCxPE off a write is in force at once anyway, §13.3.1,
//! §13.3.9) and sets UIF unless UDIS (§13.4.1). A compare match (CNT reaching CCRx)
//! sets CCxIF (§13.3.8). SR flags are rc_w0 (§13.4.5). The interrupt line is SR & DIER. Encoder mode counts the transitions
//! [`GpTimer::inputs`] is given as §13.3.12 table 53 says (with
//! [`crate::encoder::table_53`]); input channels capture CNT on their input's rising
//! edge, TI1..TI3 or TRC from an internal trigger, and MMS = 011 makes TRGO pulse at
//! each CC1 capture (`inputs`, `trigger`). Not modelled: down and centre-aligned
//! counting, the input filters (they delay an edge by a few samples, §13.4.7), TI4,
//! capture on falling edges or with a prescaler, TRGO other than the compare pulse,
//! slave modes other than the encoder's, one-pulse mode, DMA requests, TIM5's OR
//! remap.

mod inputs;
pub mod trigger;

use super::RegFile;
use crate::addr::off::{ARR, CCER, CCMR1, CCMR2, CCR1, CNT, CR1, DIER, EGR, PSC, SMCR, SR};
use crate::{EncoderCapture, PreloadClear};

const CEN: u32 = 1;
const UDIS: u32 = 2;
const URS: u32 = 4;
const ARPE: u32 = 0x80;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpTimer {
    regs: RegFile,
    max: u32,
    channels: usize,
    cnt: u32,
    /// prescaler counter
    pc: u64,
    /// timer-clock ticks owed, in units of 1/sysclk (clock ratio remainder)
    rem: u64,
    /// CPU cycle advanced to
    t: u64,
    psc: u64,
    arr: u32,
    ccr: [u32; 4],
    /// TI1, TI2, TI3 as last given
    ti: [bool; 3],
    /// update events so far
    pub updates: u64,
    /// what a CC1 capture on a counted TI1 edge latches
    encoder_capture: EncoderCapture,
    /// TRGO pulses made and not yet taken by `take_trgo`
    trgo: u32,
    /// what clearing OCxPE does to a waiting CCRx
    preload_clear: PreloadClear,
}

impl GpTimer {
    /// `bits`: 16, or 32 for TIM2/TIM5 (§13.1); `channels`: 4, or 1 for TIM10 (§14.1).
    pub fn new(bits: u32, channels: usize) -> GpTimer {
        let max = if bits == 32 { u32::MAX } else { 0xFFFF };
        GpTimer {
            regs: RegFile::new(&[(ARR, max)]), // §13.4.12: ARR resets to all ones
            max,
            channels,
            cnt: 0,
            pc: 0,
            rem: 0,
            t: 0,
            psc: 0,
            arr: max,
            ccr: [0; 4],
            ti: [false; 3],
            updates: 0,
            encoder_capture: EncoderCapture::default(),
            trgo: 0,
            preload_clear: PreloadClear::default(),
        }
    }

    /// The reading of clearing OCxPE this timer follows ([`PreloadClear`]).
    pub fn set_preload_clear(&mut self, r: PreloadClear) {
        self.preload_clear = r;
    }

    /// The reading of a capture on a counted edge this timer follows (the emulator's
    /// `Params::encoder_capture`).
    pub fn set_encoder_capture(&mut self, c: EncoderCapture) {
        self.encoder_capture = c;
    }

    pub fn get(&self, off: u32) -> u32 {
        self.regs.get(off)
    }

    fn counting(&self) -> bool {
        self.regs.get(CR1) & CEN != 0 && self.regs.get(SMCR) & 7 == 0 && self.arr != 0
    }

    /// Whether SMS selects an encoder mode (§13.4.3: 001, 010, 011).
    pub fn encoder_mode(&self) -> bool {
        (1..=3).contains(&(self.regs.get(SMCR) & 7))
    }

    /// Time moves to CPU cycle `now`, with the CPU at `sysclk` and this timer's
    /// kernel clock at `clk` (§6.2: the APB timer clock).
    pub fn advance(&mut self, now: u64, sysclk: u64, clk: u64) {
        if now <= self.t {
            return;
        }
        self.rem += (now - self.t) * clk;
        self.t = now;
        let ticks = self.rem / sysclk;
        self.rem %= sysclk;
        if !self.counting() || ticks == 0 {
            return;
        }
        self.tick(ticks);
    }

    /// `ticks` kernel clocks. The prescaler's new ratio "is taken into account at the
    /// next update event" (§13.3.1): the clocks after an update count at the PSC it
    /// loaded, so the counting goes one update at a time.
    fn tick(&mut self, mut ticks: u64) {
        while ticks > 0 && self.counting() {
            let top = if self.cnt <= self.arr { self.arr } else { self.max } as u64;
            let to_update = (top - self.cnt as u64 + 1) * (self.psc + 1) - self.pc;
            if ticks < to_update {
                let total = self.pc + ticks;
                self.pc = total % (self.psc + 1);
                self.count((total / (self.psc + 1)) as i64);
                return;
            }
            ticks -= to_update;
            self.pc = 0;
            self.count((top - self.cnt as u64 + 1) as i64);
        }
    }

    /// Encoder counts (±) from the encoder interface (§13.3.12): up through ARR to
    /// 0 is an overflow, down through 0 to ARR an underflow; both are update events.
    pub fn count_by(&mut self, d: i64) {
        if self.regs.get(CR1) & CEN == 0 {
            return;
        }
        if d >= 0 {
            self.count(d);
            return;
        }
        for _ in 0..-d {
            if self.cnt == 0 {
                self.cnt = self.arr;
                self.overflow();
            } else {
                self.cnt -= 1;
            }
            self.compare(self.cnt, self.cnt, false);
        }
    }

    /// CCxS of channel `i` (CCMRx bits 1:0 / 9:8, §13.4.7): 00 = output.
    fn is_output(&self, i: usize) -> bool {
        let off = if i < 2 { CCMR1 } else { CCMR2 };
        self.regs.get(off) >> (8 * (i % 2)) & 3 == 0
    }

    /// §13.4.5 CCxIF: "if channel CCx is configured as output: set by hardware when
    /// the counter matches the compare value"; an input channel's flag is set only
    /// by a capture.
    fn compare(&mut self, lo: u32, hi: u32, wrapped: bool) {
        for i in 0..self.channels {
            if !self.is_output(i) {
                continue;
            }
            let c = self.ccr[i];
            if (lo..=hi).contains(&c) || (wrapped && c == 0) {
                self.regs.set(SR, self.regs.get(SR) | 2 << i); // CCxIF
                if i == 0 {
                    self.cc1_event();
                }
            }
        }
    }

    fn count(&mut self, mut incs: i64) {
        while incs > 0 {
            let top = if self.cnt <= self.arr { self.arr } else { self.max };
            let to_ovf = (top - self.cnt) as i64 + 1;
            let k = incs.min(to_ovf);
            let (lo, hi) = (self.cnt.wrapping_add(1), self.cnt.wrapping_add((k - 1) as u32).wrapping_add(1));
            incs -= k;
            if k == to_ovf {
                self.compare(lo, top, true);
                self.cnt = 0;
                self.overflow();
            } else {
                self.compare(lo, hi, false);
                self.cnt = hi;
            }
        }
    }

    fn overflow(&mut self) {
        if self.regs.get(CR1) & UDIS == 0 {
            self.update_event(true);
        }
    }

    fn load_shadows(&mut self) {
        self.psc = (self.regs.get(PSC) & 0xFFFF) as u64;
        self.arr = self.regs.get(ARR) & self.max;
        for i in 0..self.channels {
            self.ccr[i] = self.regs.get(CCR1 + 4 * i as u32) & self.max;
        }
    }

    fn update_event(&mut self, flag: bool) {
        self.load_shadows();
        if flag {
            self.regs.set(SR, self.regs.get(SR) | 1); // UIF
        }
        self.updates += 1;
    }

    /// OCxPE of channel `i` (CCMRx bit 3 / 11, §13.4.7).
    fn preload(&self, i: usize) -> bool {
        let off = if i < 2 { CCMR1 } else { CCMR2 };
        self.regs.get(off) >> (3 + 8 * (i % 2)) & 1 == 1
    }

    /// OCxPE written 0 on an output channel of the CCMRx starting at
    /// channel `first`. The manual says a CCRx written without the preload
    /// "is loaded permanently" (TIMx_CCR1, §13.4.13 / §14.5.10); it does not
    /// say when a value waiting in the preload moves as OCxPE is cleared, so
    /// the model offers both readings ([`PreloadClear`]): at once (the
    /// default, as the project's TIM9 model, `tim9::oc`), or not until the
    /// next CCRx write or update. ("Loaded permanently" most likely means
    /// at once; the manual does not say so of the instant OCxPE clears.)
    fn preload_cleared(&mut self, first: usize) {
        if self.preload_clear == PreloadClear::Stays {
            return;
        }
        for ch in first..(first + 2).min(self.channels) {
            if self.is_output(ch) && !self.preload(ch) {
                self.ccr[ch] = self.regs.get(CCR1 + 4 * ch as u32) & self.max;
            }
        }
    }

    /// A read; reading CCRx of an input channel clears CCxIF (§13.4.5: "cleared by
    /// software reading the TIMx_CCRx register").
    pub fn read(&mut self, off: u32) -> u32 {
        let ch = off.wrapping_sub(CCR1) / 4;
        if (CCR1..CCR1 + 16).contains(&off) && (ch as usize) < self.channels && !self.is_output(ch as usize) {
            self.regs.set(SR, self.regs.get(SR) & !(2 << ch));
        }
        match off {
            CNT => self.cnt,
            EGR => 0, // §13.4.6: write-only
            _ => self.regs.get(off),
        }
    }

    pub fn write(&mut self, off: u32, value: u32, mask: u32) {
        let v = value & mask;
        if self.channels == 1 {
            one_channel_bits(off, v);
        }
        match off {
            SR => self.regs.set(SR, self.regs.get(SR) & (value | !mask)), // rc_w0
            CNT => self.cnt = (self.cnt & !mask | v) & self.max,
            EGR => self.write_egr(v),
            _ => {
                self.regs.write(off, value, mask);
                let ch = off.wrapping_sub(CCR1) / 4;
                if off == ARR && self.regs.get(CR1) & ARPE == 0 {
                    self.arr = self.regs.get(ARR) & self.max;
                } else if off == CCMR1 || off == CCMR2 {
                    self.preload_cleared(if off == CCMR1 { 0 } else { 2 });
                } else if (CCR1..CCR1 + 16).contains(&off)
                    && (ch as usize) < self.channels
                    && !self.preload(ch as usize)
                {
                    self.ccr[ch as usize] = self.regs.get(off) & self.max;
                }
            }
        }
    }

    /// §13.4.6: UG re-initialises the counter ("the counter is cleared ... or takes
    /// the auto-reload value if DIR = 1") and the prescaler, and makes an update
    /// event (UIF unless URS), except with UDIS, which still restarts the counters
    /// (§13.3.2); CCxG sets CCxIF.
    fn write_egr(&mut self, v: u32) {
        if v & 1 != 0 {
            self.pc = 0;
            if self.regs.get(CR1) & UDIS == 0 {
                self.update_event(self.regs.get(CR1) & URS == 0);
            }
            self.cnt = if self.regs.get(CR1) & 0x10 != 0 { self.arr } else { 0 };
        }
        for i in 0..self.channels {
            if v >> (i + 1) & 1 != 0 {
                self.regs.set(SR, self.regs.get(SR) | 2 << i);
            }
        }
    }

    /// The interrupt line (SR & DIER, §13.4.4), limited to `flags`.
    pub fn irq(&self, flags: u32) -> bool {
        self.regs.get(SR) & self.regs.get(DIER) & flags != 0
    }

    /// The CPU cycle of the next update or compare event that can raise an
    /// interrupt, or `None`.
    pub fn next_event(&self, sysclk: u64, clk: u64) -> Option<u64> {
        let dier = self.regs.get(DIER) & 0x1F;
        if !self.counting() || dier == 0 {
            return None;
        }
        let top = if self.cnt <= self.arr { self.arr } else { self.max } as u64;
        let cnt = self.cnt as u64;
        let mut incs = u64::MAX;
        if dier & 1 != 0 {
            incs = top - cnt + 1;
        }
        for i in (0..self.channels).filter(|&i| self.is_output(i)) {
            if dier >> (i + 1) & 1 != 0 {
                let d = (self.ccr[i] as u64 + top + 1 - cnt) % (top + 1);
                incs = incs.min(if d == 0 { top + 1 } else { d });
            }
        }
        let ticks = (incs as u128 - 1) * (self.psc as u128 + 1) + (self.psc + 1 - self.pc) as u128;
        let cycles = (ticks * sysclk as u128 - self.rem as u128).div_ceil(clk as u128);
        Some(self.t + (cycles.min(u64::MAX as u128 / 2) as u64).max(1))
    }

    /// OCxREF of channel `ch` in the forced and PWM modes (§13.3.9, §13.4.7 OCxM):
    /// 100 forced low, 101 forced high, 110 PWM 1, 111 PWM 2; other modes read low.
    pub fn oc_ref(&self, ch: usize) -> bool {
        let c = self.ccr[ch];
        match self.oc_mode(ch) {
            5 => true,
            6 => self.cnt < c,
            7 => self.cnt >= c,
            _ => false,
        }
    }

    /// The compare value in force for channel `ch` (the shadow: what the
    /// pin follows), where `get(CCRx)` reads what was written (the preload
    /// while OCxPE is set, §13.3.9).
    pub fn active_ccr(&self, ch: usize) -> u32 {
        self.ccr[ch]
    }

    pub fn oc_mode(&self, ch: usize) -> u32 {
        let off = if ch < 2 { CCMR1 } else { CCMR2 };
        self.regs.get(off) >> (4 + 8 * (ch % 2)) & 7
    }

    /// The level at OCx's pin, `None` while CCxE = 0 (§13.4.9 table "Output control
    /// bit for standard OCx channels"); CCxP inverts.
    pub fn oc_out(&self, ch: usize) -> Option<bool> {
        let ccer = self.regs.get(CCER);
        (ccer >> (4 * ch) & 1 == 1).then(|| self.oc_ref(ch) ^ (ccer >> (4 * ch + 1) & 1 == 1))
    }
}

/// TIM10/11's registers (§14.5) have fewer bits than TIM2–5's: a write to
/// any other (reserved, or a TIM2–5 feature this timer lacks: OPM, DIR,
/// CMS, a slave mode, channels 2–4) is not modelled. CR1 §14.5.1 (CEN,
/// UDIS, URS, ARPE, CKD), DIER §14.5.2 (UIE, CC1IE), EGR §14.5.4 (UG,
/// CC1G), CCMR1 §14.5.5 (channel 1's byte; bit 7 reserved in output mode),
/// CCER §14.5.6 (CC1E, CC1P, CC1NP), no CCR2–4. (SR is rc_w0: writing 1
/// to a bit leaves it, so any is allowed.)
fn one_channel_bits(off: u32, v: u32) {
    let allowed = match off {
        CR1 => 0x387,
        DIER => 0x3,
        EGR => 0x3,
        // output mode: bit 7 reserved; input mode: IC1F is bits 7:4
        CCMR1 => {
            if v & 3 == 0 {
                0x7F
            } else {
                0xFF
            }
        }
        CCER => 0xB,
        SMCR | CCMR2 => 0,
        o if (CCR1 + 4..CCR1 + 16).contains(&o) => 0,
        _ => u32::MAX,
    };
    if v & !allowed != 0 {
        crate::unmodelled(&format!(
            "write {v:#x} to a one-channel timer's register at {off:#x}: bits {:#x}",
            v & !allowed
        ));
    }
}

#[cfg(test)]
mod tests;
