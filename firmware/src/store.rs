//! Power-fail-safe settings in flash (after sequential-storage's approach:
//! never overwrite the only good copy). Two slots (flash sectors); a save
//! erases the older slot, writes the record, then writes a commit marker
//! last. A load takes the valid record with the highest sequence number.
//! A power cut at any point leaves the previous settings or the new ones.
//! Saves happen only while idle (the console refuses otherwise).

use polyturn_sync::codec;
use polyturn_sync::Config;

/// The hardware seam: two erasable slots, 4-byte aligned writes.
pub trait SlotFlash {
    type Error;
    fn erase(&mut self, slot: usize) -> Result<(), Self::Error>;
    fn write(&mut self, slot: usize, offset: u32, data: &[u8]) -> Result<(), Self::Error>;
    fn read(&mut self, slot: usize, offset: u32, buf: &mut [u8]) -> Result<(), Self::Error>;
}

const MARKER: [u8; 4] = *b"PTOK";
/// seq 4 + settings (padded to 52) + crc 4; the marker follows.
const BODY: usize = 4 + 52 + 4;
pub const RECORD: usize = BODY + 4;

/// What loading found (reported at boot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loaded {
    Saved {
        seq: u32,
    },
    /// nothing valid in flash: the defaults are in use
    Defaults,
}

fn body(cfg: &Config, seq: u32) -> [u8; BODY] {
    let mut b = [0xFFu8; BODY];
    b[..4].copy_from_slice(&seq.to_le_bytes());
    b[4..4 + codec::LEN].copy_from_slice(&codec::encode(cfg));
    let crc = codec::crc32(&b[..BODY - 4]);
    b[BODY - 4..].copy_from_slice(&crc.to_le_bytes());
    b
}

fn parse(rec: &[u8; RECORD]) -> Option<(u32, Config)> {
    if rec[BODY..] != MARKER {
        return None;
    }
    let crc = u32::from_le_bytes([rec[BODY - 4], rec[BODY - 3], rec[BODY - 2], rec[BODY - 1]]);
    if codec::crc32(&rec[..BODY - 4]) != crc {
        return None;
    }
    let seq = u32::from_le_bytes([rec[0], rec[1], rec[2], rec[3]]);
    codec::decode(&rec[4..4 + codec::LEN]).ok().map(|c| (seq, c))
}

fn read_slot<F: SlotFlash>(f: &mut F, slot: usize) -> Option<(u32, Config)> {
    let mut rec = [0u8; RECORD];
    f.read(slot, 0, &mut rec).ok()?;
    parse(&rec)
}

/// Newer of two sequence numbers, wrapping.
fn newer(a: u32, b: u32) -> bool {
    (a.wrapping_sub(b) as i32) > 0
}

/// Loads the newest valid settings, or the defaults. Never panics.
pub fn load<F: SlotFlash>(f: &mut F) -> (Config, Loaded) {
    match (read_slot(f, 0), read_slot(f, 1)) {
        (Some(a), Some(b)) => {
            let (seq, c) = if newer(b.0, a.0) { b } else { a };
            (c, Loaded::Saved { seq })
        }
        (Some((seq, c)), None) | (None, Some((seq, c))) => (c, Loaded::Saved { seq }),
        (None, None) => (Config::default(), Loaded::Defaults),
    }
}

/// Saves `cfg` into the slot not holding the newest record.
pub fn save<F: SlotFlash>(f: &mut F, cfg: &Config) -> Result<u32, F::Error> {
    let (a, b) = (read_slot(f, 0), read_slot(f, 1));
    let (slot, seq) = match (a, b) {
        (Some(a), Some(b)) if newer(b.0, a.0) => (0, b.0.wrapping_add(1)),
        (Some(a), _) => (1, a.0.wrapping_add(1)),
        (None, Some(b)) => (0, b.0.wrapping_add(1)),
        (None, None) => (0, 1),
    };
    f.erase(slot)?;
    f.write(slot, 0, &body(cfg, seq))?;
    f.write(slot, BODY as u32, &MARKER)?;
    Ok(seq)
}

#[cfg(test)]
mod tests;
