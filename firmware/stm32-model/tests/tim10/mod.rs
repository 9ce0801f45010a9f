//! TIM10 as the BLDC drive's tests see it: the model of a general-purpose
//! timer (RM0383 §14: TIM10, one channel) behind the firmware's `Bus`,
//! with the time of a CPU clock at 96 MHz, under either reading of
//! clearing OC1PE (`PreloadClear`).
#![allow(dead_code)]

use polyturn_firmware::bldcout::{Out, TIM10};
use polyturn_firmware::regs::{apply, Bus, Op};
use polyturn_stm32_model::chip::gptimer::GpTimer;
use polyturn_stm32_model::PreloadClear;
use polyturn_sync::Config;

pub const HZ: u64 = 96_000_000;
/// The core's default full scale (max-rate 200 kHz), Q16 counts per tick.
pub const MAX: i64 = (200_000 << 16) / polyturn_firmware::board::TICK_HZ as i64;
pub const READINGS: [PreloadClear; 2] = [PreloadClear::AtOnce, PreloadClear::Stays];

pub struct Tim10 {
    pub t: GpTimer,
    pub now: u64,
    /// CPU cycles each write takes (0: none)
    pub gap: u64,
    /// cycles the pin was high during the writes' gaps
    pub high_in_gaps: u64,
    /// the last cycle of a gap the pin was high at
    pub last_high_at: u64,
    /// a compare value to watch: cycles of the gaps the pin was high with
    /// it in force go to `watched_high`
    pub watch: Option<u32>,
    pub watched_high: u64,
}

impl Bus for Tim10 {
    fn write(&mut self, addr: u32, value: u32) {
        self.t.write(addr - TIM10, value, u32::MAX);
        self.pass(self.gap);
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.t.read(addr - TIM10)
    }
    fn delay(&mut self, _: u32) {}
}

impl Tim10 {
    /// TIM10 after `o`'s set-up, its words taking no time.
    pub fn set_up(o: &Out, reading: PreloadClear) -> Tim10 {
        let mut t = GpTimer::new(16, 1);
        t.set_preload_clear(reading);
        let mut b = Tim10 { t, now: 0, gap: 0, high_in_gaps: 0, last_high_at: 0, watch: None, watched_high: 0 };
        apply(&o.program(), &mut b).unwrap();
        b
    }

    /// The pin's level, `cycles` CPU cycles on.
    pub fn after(&mut self, cycles: u64) -> bool {
        self.now += cycles;
        self.t.advance(self.now, HZ, HZ);
        self.pin()
    }

    /// `cycles` on, a cycle at a time, counting the high ones (the gaps').
    pub fn pass(&mut self, cycles: u64) {
        for _ in 0..cycles {
            if self.after(1) {
                self.high_in_gaps += 1;
                self.last_high_at = self.now;
                self.watched_high += (Some(self.t.active_ccr(0)) == self.watch) as u64;
            }
        }
    }

    pub fn pin(&self) -> bool {
        self.t.oc_out(0).expect("CC1E on: the pin is driven")
    }

    /// How long the pin stays high from now, cycles (µs steps, at most a
    /// 25 ms look).
    pub fn high_for(&mut self) -> u64 {
        (0..25_000).take_while(|_| self.after(96)).count() as u64 * 96
    }

    /// How long the pin stays low from now, cycles (µs steps, at most 25 ms).
    pub fn low_for(&mut self) -> u64 {
        (0..25_000).take_while(|_| !self.after(96)).count() as u64 * 96
    }

    /// From a frame's start: (high cycles, frame cycles), sampled every
    /// `step` cycles over two frames.
    pub fn measure(&mut self, step: u64, frame: u64) -> (u64, u64) {
        let samples: Vec<bool> = (0..2 * frame / step).map(|_| self.after(step)).collect();
        let first = &samples[..(frame / step) as usize];
        let high = first.iter().filter(|&&h| h).count() as u64 * step;
        // the next frame's pulse begins where the first ends (sample k is
        // at (k + 1) × step)
        let rise = samples.windows(2).position(|w| !w[0] && w[1]).map(|i| (i as u64 + 2) * step);
        (high, rise.unwrap_or(0))
    }

    /// `ops` one write at a time, `gap` cycles after each; `check(i, self)`
    /// after word `i`.
    pub fn word_by_word(&mut self, ops: &[Op], gap: u64, mut check: impl FnMut(usize, &mut Tim10)) {
        for (i, op) in ops.iter().enumerate() {
            let Op::Write(a, v) = *op else { panic!("TIM10's words are writes") };
            self.write(a, v);
            self.after(gap);
            check(i, self);
        }
    }
}

pub fn out(name: &str, hz: &str) -> Out {
    let c = Config::default().with("bldc-out", name).unwrap().with("pwm-hz", hz).unwrap();
    Out::new(&c, MAX)
}
