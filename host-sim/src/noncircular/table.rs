//! The cam table the firmware loads: X steps at evenly spaced lathe
//! counts over the path's period, and the section that table cuts when the
//! core interpolates it (linear between points, whole steps).

use super::path::ToolPath;
use crate::geometry::Direction;
use polyturn_sync::cam::CAM_POINTS;
use polyturn_sync::cam_upload::{checksum, CamHeader};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A cam table file (JSON): what `polyturn device upload-cam FILE` sends.
/// X steps are measured from the inscribed radius, outward positive.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamFile {
    pub format: String,
    /// the lathe encoder the table was made for (counts per revolution)
    pub counts_per_rev: u32,
    /// lathe counts over which the table runs once
    pub period_counts: u32,
    pub steps_per_mm: f64,
    /// the X axis limits in steps/s and steps/s²
    pub max_rate_hz: u32,
    pub max_accel: u32,
    pub points: Vec<i32>,
    /// the cutter a compensating table was made for (`polyturn
    /// compensate`); none for a single-point tool's (`polyturn cam`)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutter: Option<MadeFor>,
}

/// A compensating X motion repeats with the cutter's passes, so it fits
/// only the ratio, edges and sense it was planned for: `device upload-cam`
/// checks them against the board's before it sends anything.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MadeFor {
    pub ratio: String,
    pub edges: u32,
    /// the cutter's sense against the lathe's (`same` or `opposite`, the
    /// board's `dir`): the edges sweep the stock the other way round in
    /// the other sense, so the X motion differs. Optional so that a table
    /// written without it still parses; it is then refused (`fits`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<Direction>,
}

impl MadeFor {
    /// Whether a board set to `ratio`, `edges` and `dir` (as its console
    /// says them) cuts with the cutter this table was made for; if not, why.
    pub fn fits(&self, ratio: &str, edges: &str, dir: &str) -> Result<(), String> {
        let same_ratio = match (polyturn_sync::Ratio::parse(ratio), polyturn_sync::Ratio::parse(&self.ratio)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if !same_ratio || edges != self.edges.to_string() {
            return Err(format!(
                "the table was made for ratio {} with {} edges, the board is set to ratio {ratio} with {edges} edges: set ratio and edges on the board {CAM_OFF}, or make the table for its setup (nothing sent)",
                self.ratio, self.edges
            ));
        }
        self.same_sense(dir)
    }

    /// A table without its sense is refused rather than guessed: the X
    /// motion of the wrong sense cuts another section, and once the table
    /// is fitted the board refuses `set dir`, so the mismatch could not
    /// even be put right on the board.
    fn same_sense(&self, dir: &str) -> Result<(), String> {
        match self.direction {
            Some(d) if d.name() == dir => Ok(()),
            Some(d) => Err(format!(
                "the table was made for direction {} (the cutter turning {} the lathe), the board is set to dir={dir}: set dir {} on the board {CAM_OFF}, or make the table with --direction {dir} (nothing sent)",
                d.name(),
                if d == Direction::Same { "the same way as" } else { "the opposite way to" },
                d.name()
            )),
            None => Err(format!(
                "the table does not say which sense its cutter turns (cutter.direction, which polyturn compensate --table writes; an older polyturn did not), and its X motion fits only one: make it again with polyturn compensate --direction {dir} --table FILE for the board's dir={dir} (nothing sent)"
            )),
        }
    }
}

/// A board's settings as its console says them (`get`), those a table
/// must fit.
pub struct Board<'a> {
    pub cpr: &'a str,
    pub ratio: &'a str,
    pub edges: &'a str,
    pub drive: &'a str,
    /// the cutter's sense, `same` or `opposite`
    pub dir: &'a str,
}

/// The way out of a fitted table, for advice that changes the cutter (the
/// board refuses that while a table is fitted).
const CAM_OFF: &str = "(after polyturn device cam-off, if a table is fitted)";

impl CamFile {
    /// Whether a board with these settings runs this table with the
    /// encoder and the tool it was made for: a compensating table
    /// (`polyturn compensate`) with its cutter turning, a single-point
    /// tool's (`polyturn cam`) with none (its X motion is the whole cut).
    pub fn fits(&self, b: &Board) -> Result<(), String> {
        if b.cpr != self.counts_per_rev.to_string() {
            return Err(format!(
                "the table was made for a lathe encoder of {} counts a turn (counts_per_rev), the board's cpr is {}: set cpr on the board, or make the table for its encoder (nothing sent)",
                self.counts_per_rev, b.cpr
            ));
        }
        match (&self.cutter, b.drive == "none") {
            (Some(c), true) => Err(format!(
                "the table straightens the flats of a turning cutter (ratio {} with {} edges), the board is set to drive=none: set drive stepper or bldc {CAM_OFF}, or make a single-point tool's table with polyturn cam (nothing sent)",
                c.ratio, c.edges
            )),
            (Some(c), false) => c.fits(b.ratio, b.edges, b.dir),
            (None, true) => Ok(()),
            (None, false) => Err(format!(
                "the table is a single-point tool's (polyturn cam), the board is set to drive={}: set drive none first {CAM_OFF}, so that no cutter turns while X cuts the section (nothing sent)",
                b.drive
            )),
        }
    }

    /// The same, from the board's `get` reply (`ok cpr=C ... ratio=R ...`).
    pub fn fits_settings(&self, get_reply: &str) -> Result<(), String> {
        let value = |key: &str| {
            get_reply.split_whitespace().find_map(|w| w.split_once('=').filter(|(k, _)| *k == key).map(|(_, v)| v))
        };
        match (value("cpr"), value("ratio"), value("edges"), value("drive"), value("dir")) {
            (Some(cpr), Some(ratio), Some(edges), Some(drive), Some(dir)) => {
                self.fits(&Board { cpr, ratio, edges, drive, dir })
            }
            _ => {
                Err("the board's cpr, ratio, edges, drive and dir could not be read (get): connect to it first".into())
            }
        }
    }
}

pub const FORMAT: &str = "polyturn-cam-1";

/// X axis steps per mm of tool radius a table is made for, at least and at
/// most: under 1 a step is more than ten times the 0.1 mm a table may be
/// off its path; 100 000 is a 1 mm screw at 500 steps a turn x 200.
pub const STEPS_PER_MM: (f64, f64) = (1.0, 1e5);

/// The shortest whole-count period of a cam that repeats `sides` times
/// over `revolutions` lathe turns: one repeat when that is whole counts
/// (a finer table for the same size), else the whole pattern.
pub fn shortest_period(revolutions: u32, counts_per_rev: u32, sides: u32) -> u32 {
    let all = revolutions.max(1) * counts_per_rev;
    if all.is_multiple_of(sides.max(1)) {
        all / sides.max(1)
    } else {
        all
    }
}

/// A path over m revolutions repeats every m/N revolution (one cut and one
/// link).
pub fn period_counts(path: &dyn ToolPath, counts_per_rev: u32) -> u32 {
    shortest_period(path.revolutions(), counts_per_rev, path.polygon().sides)
}

/// Samples the path at CAM_POINTS (at most one per count) over its period.
pub fn build(path: &dyn ToolPath, counts_per_rev: u32, steps_per_mm: f64, rates: (u32, u32)) -> CamFile {
    let period = period_counts(path, counts_per_rev);
    let n = (period as usize).min(CAM_POINTS);
    let span = TAU * period as f64 / counts_per_rev as f64;
    let points = (0..n)
        .map(|i| ((path.at(span * i as f64 / n as f64)[0] - path.polygon().apothem_mm) * steps_per_mm).round() as i32)
        .collect();
    CamFile {
        format: FORMAT.into(),
        counts_per_rev,
        period_counts: period,
        steps_per_mm,
        max_rate_hz: rates.0,
        max_accel: rates.1,
        points,
        cutter: None,
    }
}

impl CamFile {
    /// What the core's `fit_cam` and the upload's `cam begin` take.
    pub fn header(&self) -> CamHeader {
        CamHeader {
            points: self.points.len() as u32,
            period_counts: self.period_counts,
            counts_per_rev: self.counts_per_rev,
            max_rate_hz: self.max_rate_hz,
            max_accel: self.max_accel,
        }
    }

    /// The console lines that upload this table (see the sync core's
    /// `cam_upload`): begin, data (up to 8 values a line, fewer where long
    /// values would make a line longer than `max_len`), end with the CRC-32.
    pub fn upload_lines(&self, max_len: usize) -> Vec<String> {
        let h = self.header();
        let [p, period, cpr, rate, accel] = h.words();
        let mut lines = vec![format!("cam begin {p} {period} {cpr} {rate} {accel}")];
        let mut at = 0;
        while at < self.points.len() {
            let mut line = format!("cam data {at}");
            for (k, v) in self.points[at..].iter().take(8).enumerate() {
                let v = format!(" {v}");
                if k > 0 && line.len() + v.len() > max_len {
                    break;
                }
                line.push_str(&v);
                at += 1;
            }
            lines.push(line);
        }
        lines.push(format!("cam end {:08x}", checksum(&h, &self.points)));
        lines
    }

    /// The tool's radius (mm) at unwrapped lathe angle `phi`, interpolated
    /// as the core does it.
    pub fn radius(&self, apothem_mm: f64, phi: f64) -> f64 {
        let n = self.points.len();
        let at = (phi / TAU * self.counts_per_rev as f64).rem_euclid(self.period_counts as f64);
        let x = at * n as f64 / self.period_counts as f64;
        let (i, f) = (x.floor() as usize % n, x - x.floor());
        let (a, b) = (self.points[i] as f64, self.points[(i + 1) % n] as f64);
        apothem_mm + (a + (b - a) * f) / self.steps_per_mm
    }

    /// Largest |section − the path's section| (mm) the table cuts: what
    /// the core's interpolation and whole steps add.
    pub fn deviation(&self, path: &dyn ToolPath, samples: usize) -> f64 {
        let r = path.polygon().apothem_mm;
        let revs = self.period_counts.div_ceil(self.counts_per_rev).max(path.revolutions());
        (0..samples)
            .map(|k| TAU * k as f64 / samples as f64)
            .map(|phi| {
                let cut = (0..revs).map(|i| self.radius(r, phi + TAU * i as f64)).fold(f64::INFINITY, f64::min);
                (cut - path.section(phi)).abs()
            })
            .fold(0.0, f64::max)
    }
}
