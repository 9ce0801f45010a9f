//! The flash read interface of the STM32F411: its ART accelerator (RM0383 §3.4,
//! "Read interface"), as instruction fetches and literal loads meet it.
//!
//! What the manual says, and what this model takes from each statement:
//! - a flash read gives a 128-bit line and takes LATENCY + 1 HCLK cycles
//!   (FLASH_ACR.LATENCY wait states, §3.4.1, §3.8.1): [`LINE`], `read_len`;
//! - "Prefetch on the I-Code bus can be used to read the next sequential
//!   instruction line from the Flash memory while the current instruction line
//!   is being requested by the CPU" (PRFTEN): when the CPU starts on a line,
//!   the next one is read if the flash is free for it;
//! - "When the code is not sequential (branch), the instruction may not be
//!   present in the currently used instruction line or in the prefetched
//!   instruction line. In this case, the penalty in terms of number of cycles
//!   is at least equal to the number of wait states": a miss costs the wait
//!   states in the model. Reads are not said to be abandoned, so in the bound a
//!   miss first waits out a read that may be under way ([`Art::bound`]);
//! - the instruction cache (ICEN): "64 lines of 128 bits"; "Each time a miss
//!   occurs (requested data not present in the currently used instruction line,
//!   in the prefetched instruction line or in the instruction cache memory), the
//!   line read is copied into the instruction cache memory"; hits are "provided
//!   without inserting any delay"; "Once all the instruction cache memory lines
//!   have been filled, the LRU (least recently used) policy is used";
//! - literal pools go over the D-Code bus, which "has priority over accesses
//!   through the AHB instruction bus I-Code"; the data cache (DCEN) "works like
//!   the instruction cache memory, but the retained data size is limited to 8
//!   rows of 128 bits".
//!
//! Because the replacement is LRU, a line read again within 64 other lines
//! since its last use hits whatever the cache held before: a run simulated
//! from a cold cache (`flush`) can only over-count its misses. That is how the
//! bound takes "a fetch that could miss does".

/// Bytes in a flash line (128 bits, §3.4.2).
pub const LINE: u32 = 16;

/// The line an address is in.
pub fn line_of(addr: u32) -> u32 {
    addr / LINE
}

/// FLASH_ACR's fields the read interface uses (§3.8.1: LATENCY bits 0-3,
/// PRFTEN bit 8, ICEN bit 9, DCEN bit 10).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Acr {
    pub latency: u32,
    pub prefetch: bool,
    pub icache: bool,
    pub dcache: bool,
}

impl Acr {
    pub fn from_reg(v: u32) -> Acr {
        Acr { latency: v & 0xF, prefetch: v >> 8 & 1 == 1, icache: v >> 9 & 1 == 1, dcache: v >> 10 & 1 == 1 }
    }

    /// HCLK cycles a line read takes.
    pub fn read_len(&self) -> u64 {
        self.latency as u64 + 1
    }
}

/// Lines in the flash (512 KiB, RM0383 §3.3): the caches index their tags by
/// line for a lookup in one step.
const FLASH_LINES: usize = 512 * 1024 / LINE as usize;

/// A least-recently-used cache of `N` lines of the flash (tags only: the
/// bytes are the flash's). Lines are taken modulo the flash (its alias at 0
/// is the same array).
#[derive(Clone, Debug)]
pub struct Lru<const N: usize> {
    tags: [u32; N],
    used: [u64; N],
    len: usize,
    stamp: u64,
    /// slot + 1 of each flash line held, 0 if not held
    slot: Vec<u8>,
}

impl<const N: usize> Default for Lru<N> {
    fn default() -> Self {
        Lru { tags: [0; N], used: [0; N], len: 0, stamp: 0, slot: vec![0; FLASH_LINES] }
    }
}

impl<const N: usize> Lru<N> {
    fn index(line: u32) -> usize {
        line as usize % FLASH_LINES
    }

    /// Whether `line` is held; a hit makes it the most recently used.
    pub fn hit(&mut self, line: u32) -> bool {
        self.stamp += 1;
        match self.slot[Self::index(line)] {
            0 => false,
            s => {
                self.used[s as usize - 1] = self.stamp;
                true
            }
        }
    }

    /// Whether `line` is held, without using it.
    pub fn holds(&self, line: u32) -> bool {
        self.slot[Self::index(line)] != 0
    }

    /// `line` copied in, over the least recently used line once full.
    pub fn insert(&mut self, line: u32) {
        self.stamp += 1;
        let i = if self.len < N {
            self.len += 1;
            self.len - 1
        } else {
            let i = (0..N).min_by_key(|&i| self.used[i]).unwrap_or(0);
            self.slot[Self::index(self.tags[i])] = 0;
            i
        };
        (self.tags[i], self.used[i]) = (line, self.stamp);
        self.slot[Self::index(line)] = i as u8 + 1;
    }

    pub fn flush(&mut self) {
        for &t in &self.tags[..self.len] {
            self.slot[Self::index(t)] = 0;
        }
        self.len = 0;
    }
}

/// The read interface's state: the line the CPU is on, the line prefetched
/// and when it is ready, the caches, and until when the flash is busy.
#[derive(Clone, Debug, Default)]
pub struct Art {
    pub acr: Acr,
    /// the bound's rules (`bound`) rather than the model's
    pessimistic: bool,
    current: Option<u32>,
    prefetched: Option<(u32, u64)>,
    busy_until: u64,
    icache: Lru<64>,
    dcache: Lru<8>,
    /// misses so far (instruction, literal)
    pub misses: (u64, u64),
}

impl Art {
    /// What silicon most likely does.
    pub fn model() -> Art {
        Art::default()
    }

    /// What silicon cannot exceed: every miss waits out a read that may be
    /// under way (reads are not abandoned) before its own, and the caches are
    /// flushed wherever a run's cache state is not known (`flush`).
    pub fn bound() -> Art {
        Art { pessimistic: true, ..Art::default() }
    }

    /// Forgets every line held: a cold cache.
    pub fn flush(&mut self) {
        self.icache.flush();
        self.dcache.flush();
        self.current = None;
        self.prefetched = None;
    }

    /// Cycles the CPU stalls to fetch from `line` at cycle `t` (0 on a hit).
    pub fn fetch(&mut self, line: u32, t: u64) -> u64 {
        if self.current == Some(line) {
            return 0;
        }
        let len = self.acr.read_len();
        let ready = match self.prefetched.take() {
            Some((l, ready)) if l == line => ready,
            _ if self.acr.icache && self.icache.hit(line) => t,
            _ => {
                self.misses.0 += 1;
                let ready = self.start(t, len) + len - 1;
                if self.acr.icache {
                    self.icache.insert(line);
                }
                ready
            }
        };
        self.current = Some(line);
        self.prefetch(line + 1, ready.max(t), len);
        ready.saturating_sub(t)
    }

    /// Cycles a load from flash (a literal pool, a constant) stalls at `t`.
    pub fn literal(&mut self, line: u32, t: u64) -> u64 {
        if self.acr.dcache && self.dcache.hit(line) {
            return 0;
        }
        self.misses.1 += 1;
        let len = self.acr.read_len();
        let ready = self.start(t, len) + len - 1;
        if self.acr.dcache {
            self.dcache.insert(line);
        }
        ready - t
    }

    /// When a read asked for at `t` starts: once the flash is free; in the
    /// bound, a whole read later whatever this model thinks is under way.
    fn start(&mut self, t: u64, len: u64) -> u64 {
        let start = if self.pessimistic { t.max(self.busy_until) + len } else { t.max(self.busy_until) };
        self.busy_until = start + len;
        start
    }

    fn prefetch(&mut self, next: u32, from: u64, len: u64) {
        let held = self.acr.icache && self.icache.holds(next);
        if !self.acr.prefetch || held {
            return;
        }
        let start = from.max(self.busy_until);
        self.busy_until = start + len;
        self.prefetched = Some((next, start + len - 1));
    }
}

#[cfg(test)]
mod tests;
