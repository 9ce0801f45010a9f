//! The finished section: r(φ) = min(R2, min over passes), and the figures a
//! machinist reads off it (the `polyturn geometry` JSON contract).

use super::{Envelope, Setup};
use std::f64::consts::{PI, TAU};

/// A section sampled over the whole circle (or over one flat's sector,
/// repeating: [`Section::ideal_sector`]), flat 0 centred on angle 0.
#[derive(Clone, Debug)]
pub struct Section {
    pub sides: u32,
    pub stock_radius: f64,
    pub envelope: Envelope,
    /// every flat the same bins (one sector, or one tiled round the
    /// circle): flat 0 stands for all; false for a simulated cut
    pub periodic: bool,
}

/// The figures of a section (all lengths in mm).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SectionSummary {
    pub sides: u32,
    pub inscribed_radius: f64,
    pub circumscribed_radius: f64,
    pub across_flats: Option<f64>,
    pub flat_deviation: f64,
    pub corners_sharp: bool,
}

/// Samples along one pass: enough that each straight piece is ≲ 0.5 µm of
/// path, so linear interpolation stays far inside the 1 µm accuracy target.
fn pass_samples(setup: &Setup) -> usize {
    let w = setup.pass_half_window();
    let speed = setup.centre_distance() + setup.k().abs() * setup.cutter_radius_mm;
    ((2.0 * w * speed / 5e-4) as usize).clamp(4_000, 400_000)
}

/// Pass 0's in-stock path, a ∈ [−a_e, a_e], as work-frame points.
pub fn pass_points(setup: &Setup, samples: usize) -> Vec<(f64, f64)> {
    let w = setup.pass_half_window();
    (0..=samples).map(|i| setup.tip(-w + 2.0 * w * i as f64 / samples as f64, 0.0)).collect()
}

impl Section {
    /// The exact model's section with `bins_per_side` samples per flat.
    pub fn ideal(setup: &Setup, bins_per_side: usize) -> Section {
        Section::from_pass(setup, &pass_points(setup, pass_samples(setup)), bins_per_side)
    }

    /// One sector of the exact model's section (the envelope's period is
    /// 2π/N, so every flat and corner reads the same bins), each bin's radius
    /// solved for on the pass itself: [`Section::ideal`]'s bins to within its
    /// polyline's interpolation (≤ 1e-7 mm at R2 = 10 mm), at a small
    /// fraction of the cost. `summary` works on it but walks all N flats;
    /// flat 0 and corner 0 stand for every one.
    pub fn ideal_sector(setup: &Setup, bins_per_side: usize) -> Section {
        let n = setup.sides().max(1);
        let envelope = super::sector::sector_envelope(setup, bins_per_side);
        Section { sides: n, stock_radius: setup.stock_radius_mm, envelope, periodic: true }
    }

    /// The section cut by one pass's path (work-frame points, flat 0 in
    /// the middle) and its N rotations: every pass is a rotation of pass 0
    /// by a multiple of 2π/N (see the module notes). One sector is cut,
    /// corners at ±π/N, then repeated round the circle.
    pub fn from_pass(setup: &Setup, pass: &[(f64, f64)], bins_per_side: usize) -> Section {
        let sector = TAU / setup.sides().max(1) as f64;
        let mut one = Envelope::new(-sector / 2.0, sector, sector, bins_per_side, setup.stock_radius_mm);
        one.add_polyline(pass);
        Section::tiled(setup, &one)
    }

    /// [`Section::ideal`] over the whole circle from the sector solved on
    /// the pass ([`Section::ideal_sector`]): the same bins to within 1e-7 mm
    /// at a fraction of the cost (the simulator's result takes it every run).
    pub fn ideal_tiled(setup: &Setup, bins_per_side: usize) -> Section {
        Section::tiled(setup, &Section::ideal_sector(setup, bins_per_side).envelope)
    }

    /// One sector's envelope (corners at ±π/N) repeated round the circle.
    fn tiled(setup: &Setup, one: &Envelope) -> Section {
        let n = setup.sides().max(1);
        let sector = TAU / n as f64;
        let bins_per_side = one.bins();
        let total = (bins_per_side * n as usize).max(2);
        let mut env = Envelope::new(-sector / 2.0, TAU, TAU, total, setup.stock_radius_mm);
        for i in 0..total {
            env.radius[i] = one.radius[i % bins_per_side];
        }
        Section { sides: n, stock_radius: setup.stock_radius_mm, envelope: env, periodic: true }
    }

    /// Bins per flat that keep the whole circle under ~2^18 samples.
    pub fn default_bins(sides: u32) -> usize {
        ((1usize << 18) / sides.max(1) as usize).clamp(16, 4096) & !1
    }

    /// The section's radius at angle φ (flat 0's middle at φ = 0).
    pub fn radius_at(&self, phi: f64) -> f64 {
        self.envelope.at(phi)
    }

    pub fn summary(&self) -> SectionSummary {
        let r = &self.envelope.radius;
        let min = r.iter().cloned().fold(f64::INFINITY, f64::min);
        let max = r.iter().cloned().fold(0.0, f64::max);
        let n = self.sides;
        let corners_sharp = (0..n).all(|j| self.corner_radius(j) < self.stock_radius - 1e-9);
        let across_flats = n.is_multiple_of(2).then(|| {
            let half = n / 2;
            let sum: f64 = (0..half)
                .map(|j| self.radius_at(self.flat_middle(j)) + self.radius_at(self.flat_middle(j + half)))
                .sum();
            sum / half as f64
        });
        SectionSummary {
            sides: n,
            inscribed_radius: min,
            circumscribed_radius: max,
            across_flats,
            flat_deviation: self.worst_flat_deviation(),
            corners_sharp,
        }
    }

    pub fn flat_middle(&self, j: u32) -> f64 {
        TAU * j as f64 / self.sides as f64
    }
    /// Radius on the corner ray between flat j and flat j+1.
    pub fn corner_radius(&self, j: u32) -> f64 {
        self.radius_at(self.flat_middle(j) + PI / self.sides as f64)
    }

    /// The signed deviation with the largest magnitude over all flats
    /// (flat 0's where every flat has its bins).
    fn worst_flat_deviation(&self) -> f64 {
        let flats = if self.periodic { 1 } else { self.sides };
        (0..flats).map(|j| self.flat_deviation(j)).fold(0.0, |acc, d| if d.abs() > acc.abs() { d } else { acc })
    }

    /// Largest distance of flat j from the chord joining its ends (the
    /// corners, or where the cut meets the stock); + when it bulges out.
    pub fn flat_deviation(&self, j: u32) -> f64 {
        let half = PI / self.sides as f64;
        let mid = self.flat_middle(j);
        let env = &self.envelope;
        let step = env.step();
        let stock = self.stock_radius - 1e-9;
        let point = |phi: f64| {
            let r = self.radius_at(phi);
            let rel = phi - mid;
            (r * rel.cos(), r * rel.sin(), r)
        };
        // Every sample of the flat, once: the walks to its ends and the
        // search for its worst point read the same points.
        let steps = (half / step).round() as i64;
        let points: Vec<_> = (-steps..=steps).map(|i| point(mid + step * i as f64)).collect();
        let at = |i: i64| points[(i + steps) as usize];
        // Walk out from the middle to each end: a corner or the stock.
        let end = |dir: i64| {
            let mut last = at(0);
            for i in 1..=steps {
                let p = at(dir * i);
                if p.2 >= stock {
                    return last;
                }
                last = p;
            }
            last
        };
        let (a, b) = (end(-1), end(1));
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        if len < 2.0 * step * self.stock_radius {
            return 0.0; // the flat is narrower than the sampling: no chord to measure from
        }
        let mut worst: f64 = 0.0;
        for &p in &points {
            if p.2 >= stock || p.1 < a.1.min(b.1) || p.1 > a.1.max(b.1) {
                continue;
            }
            // Outward normal of the chord points away from the centre.
            let d = ((p.0 - a.0) * dy - (p.1 - a.1) * dx) / len;
            let out = if (-a.0) * dy - (-a.1) * dx > 0.0 { -d } else { d };
            if out.abs() > worst.abs() {
                worst = out;
            }
        }
        worst
    }
}
