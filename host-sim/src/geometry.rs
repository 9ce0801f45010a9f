//! The geometry model: the ground truth the simulator and firmware are
//! checked against.
//!
//! # Derivation (from the physics, not from the documents' labels)
//! Work centre at the origin, cutter centre at (X0, 0), X0 = R1 + R2 − DOC
//! (Foale, "Turning polygons on a lathe", 2022, appendix). The work turns by `a` (counter-clockwise
//! positive) and the cutter by θ = s·GR·a, with s = +1 for "same" (both
//! spindles turn the same way seen from the same end) and s = −1 for
//! "opposite". Tip 0 points at the work when θ = 0, so in the lab frame it is
//! at X0 − R1·e^{iθ}. Seen from the turning work (rotate by −a):
//!
//!   P(a) = X0·e^{−ia} − R1·e^{ika},   k = s·GR − 1.
//!
//! Checks against the documents:
//! * same sense, GR = 2: k = 1, P = (X0 − R1)cos a − i(X0 + R1) sin a, an
//!   ellipse with semi-axes X0 − R1 and X0 + R1 (Foale's "nearly magic" 2:1).
//! * |P'(a)|² = X0² + k²R1² + 2·X0·R1·k·cos(GR·a): Ghionea's eq. (5) with the
//!   upper signs (k = i − 1, cut-up milling) for same sense and the lower
//!   (k = −(i + 1), cut-down) for opposite, since X0/R_T = 1 + R_c/R_T.
//! * |P(a)|² = X0² + R1² − 2·X0·R1·cos(GR·a) grows with |a| over one cutter
//!   turn, so each pass is one contiguous cut, deepest (R2 − DOC) in the middle.
//! * Foale's appendix formulas (a ± b) agree with this once mirrored; his text's
//!   "11/3 with 3 cutting tools will create a 4 sided shape" does not: 11/3 × 3
//!   cuts 11 flats (and 4/3 × 3 cuts the square).
//! * Every pass of every edge is the same curve rotated by a multiple of
//!   2π/N (a time shift Δ of pass 0 equals a rotation by Δ when s·GR·Δ is a
//!   multiple of 2π/Z), so one pass and N rotations give the whole section.

pub mod alignment;
mod envelope;
pub mod roundness;
pub mod section;
mod sector;
pub mod svg;

pub use envelope::Envelope;
pub use roundness::Roundness;
pub use section::{Section, SectionSummary};

use polyturn_sync::Ratio;
use std::f64::consts::PI;

/// Relative sense of rotation of cutter and work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    Same,
    Opposite,
}

impl Direction {
    pub fn sign(self) -> f64 {
        match self {
            Direction::Same => 1.0,
            Direction::Opposite => -1.0,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Direction::Same => "same",
            Direction::Opposite => "opposite",
        }
    }
}

/// Most edges a cutter may have (the planner's and the CLI's limit).
pub const MAX_EDGES: u32 = 12;

/// The lengths a setup takes, mm: a micron (finer is no lathe's) to ten
/// metres (a lathe, not a bridge). The CLI's length flags take the same.
pub const LENGTH_MM: (f64, f64) = (0.001, 10_000.0);

/// One polygon-turning setup: Foale's five variables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    pub cutter_radius_mm: f64,
    pub stock_radius_mm: f64,
    pub depth_mm: f64,
    pub ratio: Ratio,
    pub edges: u32,
    pub direction: Direction,
}

/// A setup value out of range: the field and what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct SetupError {
    pub field: &'static str,
    pub allowed: String,
}

/// Why `Setup::check` refuses a setup.
#[derive(Clone, Debug)]
pub enum Refusal {
    /// a value out of its range
    Setting(SetupError),
    /// the section is nearly round
    Round(Roundness),
}

fn positive_finite(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

impl Setup {
    /// Checks every field; the error names the CLI flag it came from.
    pub fn validate(&self) -> Result<(), SetupError> {
        let err = |field, allowed: &str| Err(SetupError { field, allowed: allowed.to_string() });
        // in the flag's own range and words: a cutter `setups` assumes
        // (5 x the stock) is refused here as `geometry` refuses the flag
        if !(LENGTH_MM.0..=LENGTH_MM.1).contains(&self.cutter_radius_mm) {
            return Err(SetupError {
                field: "cutter-radius",
                allowed: format!("must be a number in {}..={} mm", LENGTH_MM.0, LENGTH_MM.1),
            });
        }
        if !positive_finite(self.stock_radius_mm) {
            return err("stock-radius", "must be a finite length > 0 mm");
        }
        if !positive_finite(self.depth_mm) || self.depth_mm >= self.stock_radius_mm {
            return Err(SetupError {
                field: "depth",
                allowed: format!("must be > 0 and < the stock radius ({} mm)", self.stock_radius_mm),
            });
        }
        // X0 = R1 + R2 - DOC < R2 would put the cutter's axis inside the
        // bar: no real setup, and the model's section is meaningless.
        if self.cutter_radius_mm <= self.depth_mm {
            return Err(SetupError {
                field: "cutter-radius",
                allowed: format!(
                    "must be > the depth ({} mm): a smaller cutter's axis would be inside the bar",
                    self.depth_mm
                ),
            });
        }
        if self.edges == 0 || self.edges > MAX_EDGES {
            return err("edges", "must be a whole number in 1..=12");
        }
        Ok(())
    }

    /// `geometry`'s whole check of a setup: each value in its range
    /// (`validate`), then a section that is a polygon, not a circle
    /// (`Roundness`); Ok with the section judged. `setups` lists only what
    /// it passes, so that no row it prints is one `geometry` refuses.
    pub fn check(&self) -> Result<Section, Refusal> {
        self.check_summed().map(|(section, _)| section)
    }

    /// The figures `geometry` prints for a setup it takes: its checked
    /// section's summary. `setups` prints these for each row.
    pub fn summary(&self) -> Result<SectionSummary, Refusal> {
        self.check_summed().map(|(_, summary)| summary)
    }

    /// `check`, with the section's summary it was judged by.
    fn check_summed(&self) -> Result<(Section, SectionSummary), Refusal> {
        self.validate().map_err(Refusal::Setting)?;
        let (round, section, summary) = Roundness::of_setup_summed(self);
        match round.is_round() {
            true => Err(Refusal::Round(round)),
            false => Ok((section, summary)),
        }
    }

    pub fn gr(&self) -> f64 {
        self.ratio.to_f64()
    }
    /// Centre distance X0 = R1 + R2 − DOC (Foale, appendix).
    pub fn centre_distance(&self) -> f64 {
        self.cutter_radius_mm + self.stock_radius_mm - self.depth_mm
    }
    /// Flats on the section and work turns per pattern: GR·Z = N/r.
    pub fn pattern(&self) -> (u32, u32) {
        self.ratio.pattern(self.edges)
    }
    pub fn sides(&self) -> u32 {
        self.pattern().0
    }
    /// k = s·GR − 1: the tip's turn rate seen from the work.
    pub fn k(&self) -> f64 {
        self.direction.sign() * self.gr() - 1.0
    }

    /// Tip 0's position in the work frame after the work turned by `a`, with
    /// an extra cutter angle `phase` (a phase error, in cutter radians).
    pub fn tip(&self, a: f64, phase: f64) -> (f64, f64) {
        self.tip_at(a, self.direction.sign() * (self.gr() * a + phase))
    }

    /// Tip 0's position in the work frame for a work angle `a` and a
    /// physical cutter angle `theta` (counter-clockwise, like the work).
    pub fn tip_at(&self, a: f64, theta: f64) -> (f64, f64) {
        self.tip_of(a.sin_cos(), (a - theta).sin_cos())
    }

    /// `tip_at` from the phasors' (sin, cos) of `a` and of `a − θ`:
    /// e^{−ia}·(X0 − R1·e^{iθ}) = X0·e^{−ia} − R1·e^{i(θ − a)}.
    pub fn tip_of(&self, (sa, ca): (f64, f64), (sn, cs): (f64, f64)) -> (f64, f64) {
        let (x0, r1) = (self.centre_distance(), self.cutter_radius_mm);
        (x0 * ca - r1 * cs, -x0 * sa + r1 * sn)
    }

    /// Half-width in work angle of one pass inside the stock: |P(a)| = R2 at
    /// cos(GR·a) = (X0² + R1² − R2²) / (2·X0·R1).
    pub fn pass_half_window(&self) -> f64 {
        self.in_stock_cos().acos() / self.gr()
    }

    /// A tip is inside the stock while cos(its angle from the line of
    /// centres) exceeds this.
    pub fn in_stock_cos(&self) -> f64 {
        let (x0, r1, r2) = (self.centre_distance(), self.cutter_radius_mm, self.stock_radius_mm);
        ((x0 * x0 + r1 * r1 - r2 * r2) / (2.0 * x0 * r1)).clamp(-1.0, 1.0)
    }

    /// |dP/da|: tip speed relative to the work per rad/s of the lathe
    /// (Ghionea eq. 5, see the module notes).
    pub fn relative_speed_factor(&self, a: f64) -> f64 {
        let (x0, r1, k) = (self.centre_distance(), self.cutter_radius_mm, self.k());
        (x0 * x0 + k * k * r1 * r1 + 2.0 * x0 * r1 * k * (self.gr() * a).cos()).max(0.0).sqrt()
    }

    /// Rolling (pitch) radii of work and cutter, R_rP and R_rT. Opposite
    /// sense rolls externally: Ghionea eq. (3), (4), R_rP + R_rT = X0. Same
    /// sense rolls internally, R_rP − R_rT = X0; None when GR = 1 (the tip
    /// only translates seen from the work: infinite radii).
    pub fn rolling_radii(&self) -> Option<(f64, f64)> {
        let (x0, i) = (self.centre_distance(), self.gr());
        match self.direction {
            Direction::Opposite => Some((i * x0 / (i + 1.0), x0 / (i + 1.0))),
            Direction::Same if (i - 1.0).abs() < 1e-12 => None,
            Direction::Same => Some((i * x0 / (i - 1.0).abs(), x0 / (i - 1.0).abs())),
        }
    }

    /// Cutter edges' angular spacing expressed as the lathe angle between
    /// successive passes: 2π/(GR·Z).
    pub fn pass_spacing(&self) -> f64 {
        2.0 * PI / (self.gr() * self.edges as f64)
    }
}

#[cfg(test)]
mod tests;
