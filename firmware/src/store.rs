//! Power-fail-safe settings in flash (after sequential-storage's approach:
//! never overwrite the only good copy). Two slots (flash sectors); a save
//! erases the older slot, writes the record, then writes a commit marker
//! last. A load takes the valid record with the highest sequence number.
//! A power cut at any point leaves the previous settings or the new ones.
//! Saves happen only while idle (the console refuses otherwise).

use polyturn_sync::cam::CAM_POINTS;
use polyturn_sync::cam_upload::{checksum, CamHeader};
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

/// The settings added after the first layout (`codec::ext`), written before
/// the marker too. A slot saved before they existed holds erased flash
/// there: it loads with their defaults.
pub const EXT_AT: u32 = 128;

/// The cam table follows the settings record in the same slot and is
/// written before the commit marker, so the marker vouches for both:
/// magic, the five header words, the CRC, then the points.
pub const CAM_AT: u32 = 256;
pub const CAM_POINTS_AT: u32 = CAM_AT + 32;
/// Bytes a slot must hold.
pub const SLOT_LEN: usize = CAM_POINTS_AT as usize + 4 * CAM_POINTS;
const CAM_MAGIC: [u8; 4] = *b"PCAM";

/// What loading found (reported at boot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loaded {
    Saved {
        seq: u32,
        /// the slot it came from (where its cam table is, if any)
        slot: usize,
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
    let (seq, base) = parse(&rec)?;
    let mut ext = [0u8; codec::ext::LEN];
    f.read(slot, EXT_AT, &mut ext).ok()?;
    codec::ext::decode(base, &ext).ok().map(|c| (seq, c))
}

/// Newer of two sequence numbers, wrapping.
fn newer(a: u32, b: u32) -> bool {
    (a.wrapping_sub(b) as i32) > 0
}

/// Loads the newest valid settings, or the defaults. Never panics.
pub fn load<F: SlotFlash>(f: &mut F) -> (Config, Loaded) {
    match (read_slot(f, 0), read_slot(f, 1)) {
        (Some(a), Some(b)) => {
            let ((seq, c), slot) = if newer(b.0, a.0) { (b, 1) } else { (a, 0) };
            (c, Loaded::Saved { seq, slot })
        }
        (Some((seq, c)), None) => (c, Loaded::Saved { seq, slot: 0 }),
        (None, Some((seq, c))) => (c, Loaded::Saved { seq, slot: 1 }),
        (None, None) => (Config::default(), Loaded::Defaults),
    }
}

/// Saves `cfg` (and the cam table, if one is fitted) into the slot not
/// holding the newest record. `cam` may point into the newest slot's flash:
/// that slot is not touched.
/// Why a save failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(target_os = "none", derive(defmt::Format))]
pub enum SaveError<E> {
    Flash(E),
    /// the flash took the writes without an error, but what reads back is
    /// not what was written: the save did not happen (no `ok`)
    Verify,
}

/// Saves, then reads the record (and the cam) back: `Ok` only if they
/// read back as written.
pub fn save<F: SlotFlash>(
    f: &mut F,
    cfg: &Config,
    cam: Option<(CamHeader, &[i32])>,
) -> Result<u32, SaveError<F::Error>> {
    let seq = write_record(f, cfg, cam).map_err(SaveError::Flash)?;
    let (config, how) = load(f);
    let slot_ok = matches!(how, Loaded::Saved { seq: s, .. } if s == seq) && config == *cfg;
    let cam_ok = match (cam, how) {
        (None, _) => true,
        (Some((h, _)), Loaded::Saved { slot, .. }) => load_cam(f, slot) == Some(h),
        _ => false,
    };
    if slot_ok && cam_ok {
        Ok(seq)
    } else {
        Err(SaveError::Verify)
    }
}

fn write_record<F: SlotFlash>(f: &mut F, cfg: &Config, cam: Option<(CamHeader, &[i32])>) -> Result<u32, F::Error> {
    let (a, b) = (read_slot(f, 0), read_slot(f, 1));
    let (slot, seq) = match (a, b) {
        (Some(a), Some(b)) if newer(b.0, a.0) => (0, b.0.wrapping_add(1)),
        (Some(a), _) => (1, a.0.wrapping_add(1)),
        (None, Some(b)) => (0, b.0.wrapping_add(1)),
        (None, None) => (0, 1),
    };
    f.erase(slot)?;
    if let Some((h, points)) = cam {
        write_cam(f, slot, &h, points)?;
    }
    f.write(slot, EXT_AT, &codec::ext::encode(cfg))?;
    f.write(slot, 0, &body(cfg, seq))?;
    f.write(slot, BODY as u32, &MARKER)?;
    Ok(seq)
}

fn write_cam<F: SlotFlash>(f: &mut F, slot: usize, h: &CamHeader, points: &[i32]) -> Result<(), F::Error> {
    let mut head = [0u8; 28];
    head[..4].copy_from_slice(&CAM_MAGIC);
    for (i, w) in h.words().iter().chain(&[checksum(h, points)]).enumerate() {
        head[4 + 4 * i..8 + 4 * i].copy_from_slice(&w.to_le_bytes());
    }
    f.write(slot, CAM_AT, &head)?;
    let mut buf = [0u8; 256];
    for (k, chunk) in points.chunks(64).enumerate() {
        for (i, p) in chunk.iter().enumerate() {
            buf[4 * i..4 * i + 4].copy_from_slice(&p.to_le_bytes());
        }
        f.write(slot, CAM_POINTS_AT + 256 * k as u32, &buf[..4 * chunk.len()])?;
    }
    Ok(())
}

/// The cam table saved with the settings in `slot`, if its header and
/// checksum hold (the points stay in flash: the firmware maps them).
pub fn load_cam<F: SlotFlash>(f: &mut F, slot: usize) -> Option<CamHeader> {
    let mut head = [0u8; 28];
    f.read(slot, CAM_AT, &mut head).ok()?;
    let word = |i: usize| u32::from_le_bytes([head[4 + 4 * i], head[5 + 4 * i], head[6 + 4 * i], head[7 + 4 * i]]);
    let h = CamHeader {
        points: word(0),
        period_counts: word(1),
        counts_per_rev: word(2),
        max_rate_hz: word(3),
        max_accel: word(4),
    };
    if head[..4] != CAM_MAGIC || !(2..=CAM_POINTS as u32).contains(&h.points) {
        return None;
    }
    let mut points = [0i32; CAM_POINTS];
    let mut b = [0u8; 4];
    for (i, p) in points.iter_mut().take(h.points as usize).enumerate() {
        f.read(slot, CAM_POINTS_AT + 4 * i as u32, &mut b).ok()?;
        *p = i32::from_le_bytes(b);
    }
    (checksum(&h, &points[..h.points as usize]) == word(5)).then_some(h)
}

#[cfg(test)]
mod tests;
