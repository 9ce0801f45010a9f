//! Smooth tool paths whose minimum is a sharp-cornered polygon (the
//! noncircular turning note, "Noncircular Turning of Workpieces With Sharp
//! Corners", eq. (1): the section is min over the m revolutions of f_i(θ)).
//!
//! The tool's radius g(Φ) is a function of the unwrapped lathe angle Φ over
//! m revolutions. Cut j follows side s_j = j·m mod N (Theorem 2) along the
//! side's own straight line, r = R / cos ψ in polar form about the side's
//! centre, for |ψ| ≤ h (h = π/N reaches both corners). Between cuts a
//! quintic link, matching position, velocity and acceleration at both ends,
//! lifts the tool clear. Side j·m sits at Φ = j·2πm/N, so every cut and
//! every link is the same shape: g is periodic with Δ = 2πm/N, and one
//! quintic describes every link.

use std::f64::consts::{PI, TAU};

/// A regular polygon with side 0 centred on angle 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon {
    pub sides: u32,
    /// the inscribed circle's radius (centre to the middle of a side)
    pub apothem_mm: f64,
}

impl Polygon {
    /// The polygon's radius at workpiece angle `phi`.
    pub fn radius(&self, phi: f64) -> f64 {
        self.apothem_mm / self.side_angle(phi).cos()
    }
    /// ψ: the angle from the middle of the nearest side, in ±π/N.
    pub fn side_angle(&self, phi: f64) -> f64 {
        let s = TAU / self.sides as f64;
        (phi + s / 2.0).rem_euclid(s) - s / 2.0
    }
    /// Half the angle a side spans: the corner is at ψ = ±π/N.
    pub fn half_side(&self) -> f64 {
        PI / self.sides as f64
    }
}

/// A tool path: the tool's radius as a function of the unwrapped lathe
/// angle, periodic, repeating every `period` radians.
pub trait ToolPath {
    fn polygon(&self) -> Polygon;
    /// revolutions before the section is complete (the m of Theorem 2)
    fn revolutions(&self) -> u32;
    fn period(&self) -> f64;
    /// radius, d/dΦ and d²/dΦ² at unwrapped angle `phi`
    fn at(&self, phi: f64) -> [f64; 3];
    /// where pieces of the path meet (velocity must be continuous there)
    fn junctions(&self) -> Vec<f64>;
    /// The section the path leaves at workpiece angle `phi`: the minimum
    /// over the revolutions (the noncircular turning note, eq. (1)).
    fn section(&self, phi: f64) -> f64 {
        (0..self.revolutions()).map(|i| self.at(phi + TAU * i as f64)[0]).fold(f64::INFINITY, f64::min)
    }
}

/// r, dr/dψ, d²r/dψ² of the line r = R / cos ψ.
pub(crate) fn line(apothem: f64, psi: f64) -> [f64; 3] {
    let (s, c) = psi.sin_cos();
    [apothem / c, apothem * s / (c * c), apothem * (1.0 + s * s) / (c * c * c)]
}

/// The smooth path: cuts of half-angle `half_cut` joined by quintic links.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    pub polygon: Polygon,
    pub m: u32,
    /// half-angle of each cut: π/N for sharp corners, less to round them
    pub half_cut: f64,
    /// the link's coefficients in u ∈ [0, 1], and its length in radians
    link: [f64; 6],
    link_len: f64,
}

impl Path {
    /// Needs `half_cut` < Δ/2, so the link has a length. The link meets
    /// the cuts with their position and velocity, and with `link_accel`
    /// (mm/rad²) at both ends: the line's own curvature makes the path C2,
    /// less lowers the link's overshoot (the acceleration then steps at the
    /// junction, within the limit).
    pub fn new(polygon: Polygon, m: u32, half_cut: f64, link_accel: f64) -> Path {
        let len = TAU * m as f64 / polygon.sides as f64 - 2.0 * half_cut;
        // leaves side k at ψ = +h, arrives at side k + m at ψ = −h: the same
        // radius, the opposite slope (the line is even in ψ).
        let [p, v, _] = line(polygon.apothem_mm, half_cut);
        let link = quintic([p, v, link_accel], [p, -v, link_accel], len);
        Path { polygon, m, half_cut, link, link_len: len }
    }

    /// The path with a C2 link (acceleration continuous too).
    pub fn smooth(polygon: Polygon, m: u32, half_cut: f64) -> Path {
        Path::new(polygon, m, half_cut, line(polygon.apothem_mm, half_cut)[2])
    }

    /// Whether the tool is on a side's line (cutting) at `phi`.
    pub fn cutting(&self, phi: f64) -> bool {
        (phi + self.half_cut).rem_euclid(self.period()) <= 2.0 * self.half_cut
    }
}

impl ToolPath for Path {
    fn polygon(&self) -> Polygon {
        self.polygon
    }
    fn revolutions(&self) -> u32 {
        self.m
    }
    /// Δ = 2πm/N: one cut and one link.
    fn period(&self) -> f64 {
        TAU * self.m as f64 / self.polygon.sides as f64
    }

    fn at(&self, phi: f64) -> [f64; 3] {
        let h = self.half_cut;
        let u = (phi + h).rem_euclid(self.period()) - h;
        if u <= h {
            return line(self.polygon.apothem_mm, u);
        }
        let (x, l) = ((u - h) / self.link_len, self.link_len);
        let c = &self.link;
        let p = c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
        let d = c[1] + x * (2.0 * c[2] + x * (3.0 * c[3] + x * (4.0 * c[4] + x * 5.0 * c[5])));
        let dd = 2.0 * c[2] + x * (6.0 * c[3] + x * (12.0 * c[4] + x * 20.0 * c[5]));
        [p, d / l, dd / (l * l)]
    }

    fn junctions(&self) -> Vec<f64> {
        let (d, h) = (self.period(), self.half_cut);
        (0..self.polygon.sides).flat_map(|j| [d * j as f64 - h, d * j as f64 + h]).collect()
    }
}

/// Quintic Hermite coefficients in u ∈ [0, 1] through (p, v, a) at each end,
/// with v and a per radian over a length `len`.
fn quintic(start: [f64; 3], end: [f64; 3], len: f64) -> [f64; 6] {
    let [p0, v0, a0] = start;
    let [p1, v1, a1] = end;
    let (dp, v0, v1, a0, a1) = (p1 - p0, v0 * len, v1 * len, a0 * len * len, a1 * len * len);
    [
        p0,
        v0,
        a0 / 2.0,
        10.0 * dp - 6.0 * v0 - 4.0 * v1 - (3.0 * a0 - a1) / 2.0,
        -15.0 * dp + 8.0 * v0 + 7.0 * v1 + (3.0 * a0 - 2.0 * a1) / 2.0,
        6.0 * dp - 3.0 * (v0 + v1) - (a0 - a1) / 2.0,
    ]
}
