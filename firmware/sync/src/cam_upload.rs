//! Uploading a cam table over the console, in chunks with a checksum:
//!
//! ```text
//! cam begin <points> <period-counts> <cpr> <max-rate-hz> <max-accel>
//! cam data <offset> <v> <v> ...     (up to 8 values, offsets in order)
//! cam end <crc32 hex>               (CRC-32 of the header words and points)
//! ```
//! Nothing reaches the controller until the whole table and its checksum
//! agree; any error abandons the upload (start again with `begin`).

use crate::cam::CAM_POINTS;
use crate::codec::crc32_update;
use crate::console::number;

/// What `begin` announced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CamHeader {
    pub points: u32,
    pub period_counts: u32,
    /// the lathe encoder the table was made for
    pub counts_per_rev: u32,
    pub max_rate_hz: u32,
    pub max_accel: u32,
}

impl CamHeader {
    pub fn words(&self) -> [u32; 5] {
        [self.points, self.period_counts, self.counts_per_rev, self.max_rate_hz, self.max_accel]
    }
}

/// CRC-32 of the header words and the points, little-endian.
pub fn checksum(h: &CamHeader, points: &[i32]) -> u32 {
    let crc = h.words().iter().fold(!0, |c, w| crc32_update(c, &w.to_le_bytes()));
    !points.iter().fold(crc, |c, p| crc32_update(c, &p.to_le_bytes()))
}

/// The board's X output: at most one step per two ticks (a tick high, a
/// tick low: `firmware/src/xsteps.rs`), steps/s.
pub const X_MAX_RATE_HZ: u32 = crate::Timing::FIRMWARE.tick_hz / 2;

/// The X axis a header declares, against the board's X output: at most one
/// step per two ticks (`tick_hz / 2`), and some acceleration.
pub fn check_axis(h: &CamHeader, tick_hz: u32) -> Result<(), &'static str> {
    const _: () = assert!(X_MAX_RATE_HZ == 10_000, "the refusal below names the limit");
    if h.max_rate_hz > tick_hz / 2 || h.max_rate_hz == 0 || h.max_accel == 0 {
        return Err("cam max-rate must be 1..=10000 steps/s (one X step per two ticks), max-accel > 0");
    }
    Ok(())
}

/// Why a complete table is not taken: a reason of the points
/// (`Cam::check`) or the controller's, or what the points ask of the X
/// axis, with its figures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableRefusal {
    Text(&'static str),
    Motion(motion::MotionError),
}

impl TableRefusal {
    /// The reason without figures.
    pub fn describe(self) -> &'static str {
        match self {
            TableRefusal::Text(t) => t,
            TableRefusal::Motion(m) => m.describe(),
        }
    }
}

impl From<&'static str> for TableRefusal {
    fn from(t: &'static str) -> TableRefusal {
        TableRefusal::Text(t)
    }
}

impl core::fmt::Display for TableRefusal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TableRefusal::Text(t) => f.write_str(t),
            TableRefusal::Motion(m) => m.fmt(f),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    Begun,
    /// points received so far
    Received(usize),
    Complete(CamHeader),
}

/// The staging buffer (in the console task, not the controller).
pub struct CamUpload {
    header: Option<CamHeader>,
    got: usize,
    complete: bool,
    buf: [i32; CAM_POINTS],
}

impl Default for CamUpload {
    fn default() -> Self {
        CamUpload { header: None, got: 0, complete: false, buf: [0; CAM_POINTS] }
    }
}

/// A header field or an offset: digits, as the console's other numbers
/// (`console::number`).
fn num(w: Option<&str>) -> Result<u32, &'static str> {
    w.and_then(number::unsigned).ok_or("cam: expected a number (see help)")
}

impl CamUpload {
    /// One `cam ...` line, without the leading `cam`.
    /// An upload begun and not yet complete (an error now abandons it).
    pub fn in_progress(&self) -> bool {
        self.header.is_some() && !self.complete
    }

    pub fn line(&mut self, args: &str) -> Result<Progress, &'static str> {
        let r = self.step(args);
        if r.is_err() {
            self.header = None; // any error abandons the upload
        }
        r
    }

    fn step(&mut self, args: &str) -> Result<Progress, &'static str> {
        let mut w = args.split_ascii_whitespace();
        match w.next() {
            Some("begin") => self.begin(&mut w),
            Some("data") => self.data(&mut w),
            Some("end") => self.end(w.next()),
            _ => Err("usage: cam begin|data|end ... (see help)"),
        }
    }

    fn begin<'a>(&mut self, w: &mut impl Iterator<Item = &'a str>) -> Result<Progress, &'static str> {
        let h = CamHeader {
            points: num(w.next())?,
            period_counts: num(w.next())?,
            counts_per_rev: num(w.next())?,
            max_rate_hz: num(w.next())?,
            max_accel: num(w.next())?,
        };
        if !(2..=CAM_POINTS as u32).contains(&h.points) {
            return Err("cam begin: points must be in 2..=1024");
        }
        if h.period_counts < h.points {
            return Err("cam begin: period-counts must be >= points");
        }
        (self.header, self.got, self.complete) = (Some(h), 0, false);
        Ok(Progress::Begun)
    }

    fn data<'a>(&mut self, w: &mut impl Iterator<Item = &'a str>) -> Result<Progress, &'static str> {
        let h = self.header.ok_or("cam data: no upload in progress (cam begin first)")?;
        if num(w.next())? as usize != self.got {
            return Err("cam data: offset out of order (start again with cam begin)");
        }
        for v in w {
            if self.got >= h.points as usize {
                return Err("cam data: more points than announced");
            }
            self.buf[self.got] = number::signed(v).ok_or("cam data: values are whole steps")?;
            self.got += 1;
        }
        Ok(Progress::Received(self.got))
    }

    fn end(&mut self, crc: Option<&str>) -> Result<Progress, &'static str> {
        let h = self.header.ok_or("cam end: no upload in progress (cam begin first)")?;
        if self.got != h.points as usize {
            return Err("cam end: fewer points than announced");
        }
        let crc = crc.and_then(number::hex32).ok_or("cam end: expected a hex CRC-32")?;
        if crc != checksum(&h, &self.buf[..self.got]) {
            return Err("cam end: checksum mismatch, table discarded");
        }
        self.complete = true;
        Ok(Progress::Complete(h))
    }

    /// The received table, once `end` has checked it.
    pub fn table(&self) -> Option<(CamHeader, &[i32])> {
        let h = self.header.filter(|_| self.complete)?;
        self.buf.get(..h.points as usize).map(|p| (h, p))
    }
}

pub mod motion;

#[cfg(test)]
mod crc_tests;
#[cfg(test)]
mod motion_tests;
#[cfg(test)]
mod tests;
