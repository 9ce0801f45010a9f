//! The independent watchdog (RM0383 §15). Every key written is kept with its
//! time: 0xCCCC starts it, 0xAAAA reloads it (a pet), 0x5555 unlocks PR and RLR
//! (§15.4.1; §15.3.2 register access protection). PR/RLR updates are instant, so SR's PVU/RVU read 0. The
//! countdown runs on the LSI (17-47 kHz, datasheet table "LSI oscillator
//! characteristics"), so its timeout is a range: [`Iwdg::timeout_ns`]. The countdown
//! itself is not run; the first interval after 0xCCCC counts down from 0xFFF
//! whatever RLR holds (§15.3), so `timeout_ns` is the shortest later interval.

use super::RegFile;

pub const KR: u32 = 0x00;
pub const PR: u32 = 0x04;
pub const RLR: u32 = 0x08;
pub const SR: u32 = 0x0C;

/// The LSI's range, datasheet (DS10314) §6.3.9 table 38: 17 to 47 kHz, 32 typical.
pub const LSI_HZ: [u64; 3] = [17_000, 32_000, 47_000];

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Iwdg {
    regs: RegFile,
    unlocked: bool,
    /// (cycle, key) for every key written.
    pub keys: Vec<(u64, u16)>,
}

impl Default for Iwdg {
    fn default() -> Iwdg {
        Iwdg { regs: RegFile::new(&[(RLR, 0xFFF)]), unlocked: false, keys: Vec::new() }
    }
}

impl Iwdg {
    pub fn read(&self, off: u32) -> u32 {
        match off {
            KR | SR => 0,
            _ => self.regs.get(off),
        }
    }

    pub fn write(&mut self, off: u32, value: u32, mask: u32, now: u64) {
        let v = value & mask;
        match off {
            KR => {
                let key = (v & 0xFFFF) as u16;
                self.keys.push((now, key));
                self.unlocked = key == 0x5555;
            }
            // PR is 3 bits, RLR 12 (§15.4.2, §15.4.3)
            PR if self.unlocked => self.regs.write(off, value & 7, mask),
            RLR if self.unlocked => self.regs.write(off, value & 0xFFF, mask),
            _ => {}
        }
    }

    pub fn started_at(&self) -> Option<u64> {
        self.keys.iter().find(|k| k.1 == 0xCCCC).map(|k| k.0)
    }

    pub fn pets(&self) -> Vec<u64> {
        self.keys.iter().filter(|k| k.1 == 0xAAAA).map(|k| k.0).collect()
    }

    /// The last reload since the start (0xAAAA, or the first 0xCCCC itself) and
    /// how long the countdown from it lasts at LSI frequency `lsi_hz`: (cycle of
    /// the key, ns). None before the start: the counter runs only once 0xCCCC
    /// is written (§15.3), so a reload before it resets nothing. The first
    /// countdown runs from 0xFFF whatever RLR holds (§15.3). (RLR and PR are
    /// taken as they are now: the model applies their updates at once.)
    pub fn last_reload(&self, lsi_hz: u64) -> Option<(u64, u64)> {
        let start = self.keys.iter().position(|k| k.1 == 0xCCCC)?;
        let since = &self.keys[start..];
        let (at, key) = *since.iter().rev().find(|k| k.1 == 0xAAAA).unwrap_or(&since[0]);
        let rlr = if key == 0xCCCC { 0xFFF } else { self.regs.get(RLR) as u64 };
        let div = 4u64 << self.regs.get(PR).min(6);
        Some((at, (rlr + 1) * div * 1_000_000_000 / lsi_hz))
    }

    /// The longest time in `[from, to]` without a reload, in the keys' time
    /// unit: between `from`, each reload in the span since the start (0xAAAA,
    /// or the first 0xCCCC itself, as in `last_reload`) and `to`. 0 before the
    /// start: nothing counts down (§15.3).
    pub fn longest_gap(&self, from: u64, to: u64) -> u64 {
        let Some(start) = self.keys.iter().position(|k| k.1 == 0xCCCC) else { return 0 };
        let reloads = self.keys[start..].iter().enumerate().filter(|(i, k)| *i == 0 || k.1 == 0xAAAA);
        let mut prev = from;
        let mut gap = 0;
        for (_, &(at, _)) in reloads.filter(|(_, k)| (from..=to).contains(&k.0)) {
            gap = gap.max(at - prev);
            prev = at;
        }
        gap.max(to - prev)
    }

    /// The time from a reload to the reset at LSI frequency `lsi_hz`: (RLR + 1)
    /// periods of LSI / 4·2^PR (§15.3.3 table: prescaler /4 at PR = 0 ... /256).
    pub fn timeout_ns(&self, lsi_hz: u64) -> u64 {
        let div = 4u64 << self.regs.get(PR).min(6);
        (self.regs.get(RLR) as u64 + 1) * div * 1_000_000_000 / lsi_hz
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_longest_gap_counts_from_the_start_between_reloads_and_to_the_end() {
        let mut w = Iwdg::default();
        w.write(KR, 0xAAAA, u32::MAX, 5);
        assert_eq!(w.longest_gap(0, 100), 0, "not started");
        for (at, key) in [(10, 0xCCCC), (20, 0xAAAA), (60, 0xAAAA), (70, 0xCCCC), (75, 0xAAAA)] {
            w.write(KR, key, u32::MAX, at);
        }
        assert_eq!(w.longest_gap(10, 80), 40, "20 to 60; a second start is no reload");
        assert_eq!(w.longest_gap(10, 200), 125, "the last reload to the end");
        assert_eq!(w.longest_gap(30, 65), 30, "from 30 to the reload at 60");
    }

    #[test]
    fn a_reload_before_the_start_is_no_countdown_15_3() {
        let mut w = Iwdg::default();
        w.write(KR, 0xAAAA, u32::MAX, 5);
        assert_eq!(w.last_reload(32_000), None, "not started: nothing counts down");
        w.write(KR, 0xCCCC, u32::MAX, 10);
        // from 0xFFF at /4: 4096 × 4 / 32 kHz = 512 ms
        assert_eq!(w.last_reload(32_000), Some((10, 512_000_000)));
        w.write(KR, 0xCCCC, u32::MAX, 20);
        assert_eq!(w.last_reload(32_000), Some((10, 512_000_000)), "a second start is not a reload");
        w.write(KR, 0xAAAA, u32::MAX, 30);
        assert_eq!(w.last_reload(32_000).map(|r| r.0), Some(30));
    }

    #[test]
    fn pr_and_rlr_change_only_after_the_unlock_key() {
        let mut w = Iwdg::default();
        w.write(RLR, 100, u32::MAX, 0);
        assert_eq!(w.read(RLR), 0xFFF, "locked: §15.3.2");
        w.write(KR, 0x5555, u32::MAX, 1);
        w.write(PR, 3, u32::MAX, 2);
        w.write(RLR, 999, u32::MAX, 3);
        assert_eq!((w.read(PR), w.read(RLR)), (3, 999));
        w.write(KR, 0xCCCC, u32::MAX, 4);
        w.write(KR, 0xAAAA, u32::MAX, 9);
        assert_eq!(w.started_at(), Some(4));
        assert_eq!(w.pets(), vec![9]);
        // /32 at PR = 3, 1000 periods at 32 kHz: 1 s
        assert_eq!(w.timeout_ns(32_000), 1_000_000_000);
        assert_eq!(w.last_reload(32_000), Some((9, 1_000_000_000)));
    }

    #[test]
    fn the_first_countdown_after_the_start_runs_from_0xfff() {
        let mut w = Iwdg::default();
        assert_eq!(w.last_reload(32_000), None, "not started: no countdown");
        w.write(KR, 0x5555, u32::MAX, 1);
        w.write(RLR, 99, u32::MAX, 2);
        w.write(KR, 0xCCCC, u32::MAX, 3);
        // /4 at PR = 0: 4096 periods of 125 us
        assert_eq!(w.last_reload(32_000), Some((3, 512_000_000)));
        w.write(KR, 0xAAAA, u32::MAX, 7);
        assert_eq!(w.last_reload(32_000), Some((7, 12_500_000)));
    }
}
