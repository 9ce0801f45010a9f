//! Registers as memory: what a model does with bits the manual defines as plain
//! read/write (RM0383 §1.2, "rw: software can read and write to these bits").

use std::collections::BTreeMap;

/// Word registers by offset, each starting at its reset value.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RegFile {
    r: BTreeMap<u32, u32>,
}

impl RegFile {
    /// `resets`: (offset, reset value); every other register resets to 0.
    pub fn new(resets: &[(u32, u32)]) -> RegFile {
        RegFile { r: resets.iter().copied().collect() }
    }
    pub fn get(&self, off: u32) -> u32 {
        self.r.get(&off).copied().unwrap_or(0)
    }
    pub fn set(&mut self, off: u32, v: u32) {
        self.r.insert(off, v);
    }
    /// A write of the bits in `mask` (a byte or halfword access writes only its lanes).
    pub fn write(&mut self, off: u32, value: u32, mask: u32) {
        let v = self.get(off) & !mask | value & mask;
        self.set(off, v);
    }
    /// Bits `shift..shift+width` of register `off`.
    pub fn field(&self, off: u32, shift: u32, width: u32) -> u32 {
        self.get(off) >> shift & ((1u64 << width) - 1) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_partial_write_changes_only_its_lanes() {
        let mut f = RegFile::new(&[(4, 0x1234_5678)]);
        f.write(4, 0xAB00, 0xFF00);
        assert_eq!(f.get(4), 0x1234_AB78);
        assert_eq!(f.get(8), 0);
        assert_eq!(f.field(4, 8, 8), 0xAB);
    }
}
