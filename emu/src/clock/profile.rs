//! Where an exception's cycles go, by function: each block's cost (both
//! clocks) given to the exception running it, then to the function the
//! block is in (`polyturn-emu --profile`).

use super::Cost;
use std::collections::HashMap;

pub struct Profile {
    /// (exception number, block address) → cycles
    blocks: HashMap<(usize, u32), (u64, u64)>,
    /// the model's cycles in which blocks are counted
    pub window: std::ops::Range<u64>,
}

impl Default for Profile {
    fn default() -> Profile {
        Profile { blocks: HashMap::new(), window: 0..u64::MAX }
    }
}

impl Profile {
    pub fn add(&mut self, exc: usize, addr: u32, c: Cost) {
        let e = self.blocks.entry((exc, addr)).or_default();
        e.0 += c.model as u64;
        e.1 += c.bound as u64;
    }

    /// Exception `exc`'s blocks: (address, model, bound), most first.
    pub fn blocks(&self, exc: usize) -> Vec<(u32, u64, u64)> {
        let mut v: Vec<(u32, u64, u64)> =
            self.blocks.iter().filter(|(k, _)| k.0 == exc).map(|(k, v)| (k.1, v.0, v.1)).collect();
        v.sort_by_key(|r| std::cmp::Reverse(r.2));
        v
    }

    /// Exception `exc`'s cycles by function (named by `name`), most first:
    /// (function, model, bound).
    pub fn functions(&self, exc: usize, name: impl Fn(u32) -> String) -> Vec<(String, u64, u64)> {
        let mut by: HashMap<String, (u64, u64)> = HashMap::new();
        for (&(e, addr), &(m, b)) in &self.blocks {
            if e == exc {
                let f = by.entry(name(addr)).or_default();
                (f.0, f.1) = (f.0 + m, f.1 + b);
            }
        }
        let mut v: Vec<(String, u64, u64)> = by.into_iter().map(|(f, (m, b))| (f, m, b)).collect();
        v.sort_by_key(|r| std::cmp::Reverse(r.2));
        v
    }
}
