//! The fallback when the X axis cannot make sharp corners at this speed:
//! the polygon with each corner rounded to a fillet of radius ρ, tracked
//! directly in one revolution. A rounded polygon is smooth (C1), so it
//! needs no sequence of passes: the tool follows the side's line to the
//! fillet, the fillet to the next line. Its steepest slope is the line's at
//! the tangent point and its sharpest turn is the fillet, both easing as ρ
//! grows, so the smallest ρ within the axis limits is found by bisection.

use super::path::{line, Polygon, ToolPath};
use std::f64::consts::TAU;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rounded {
    pub polygon: Polygon,
    /// fillet radius, mm
    pub radius_mm: f64,
}

impl Rounded {
    /// Distance of the fillet's centre from the axis: it sits on the corner
    /// bisector (ψ = π/N), ρ inside both side lines.
    fn centre(&self) -> f64 {
        (self.polygon.apothem_mm - self.radius_mm) / self.polygon.half_side().cos()
    }
    /// ψ of the tangent point on the side (side frame: the line is x = R).
    pub fn tangent(&self) -> f64 {
        (self.centre() * self.polygon.half_side().sin() / self.polygon.apothem_mm).atan()
    }
    /// Radius at the fillet's apex (on the bisector): the corner falls
    /// short of the sharp one by R/cos(π/N) − this.
    pub fn apex(&self) -> f64 {
        self.centre() + self.radius_mm
    }
    /// The corner material left, mm: sharp corner radius − apex.
    pub fn shortfall(&self) -> f64 {
        self.polygon.apothem_mm / self.polygon.half_side().cos() - self.apex()
    }

    /// r on the fillet at |ψ| ≥ tangent: the ray meets the circle of
    /// radius ρ about the centre at r = d cos δ + sqrt(ρ² − d² sin² δ).
    fn fillet(&self, psi: f64) -> f64 {
        let (d, rho) = (self.centre(), self.radius_mm);
        let delta = psi.abs() - self.polygon.half_side();
        d * delta.cos() + (rho * rho - (d * delta.sin()).powi(2)).max(0.0).sqrt()
    }
}

impl ToolPath for Rounded {
    fn polygon(&self) -> Polygon {
        self.polygon
    }
    fn revolutions(&self) -> u32 {
        1
    }
    fn period(&self) -> f64 {
        TAU / self.polygon.sides as f64
    }

    fn at(&self, phi: f64) -> [f64; 3] {
        let psi = self.polygon.side_angle(phi);
        if psi.abs() <= self.tangent() {
            return line(self.polygon.apothem_mm, psi);
        }
        // the fillet's derivatives by central differences: the circle
        // formula is smooth through the tangent point and the apex
        let (e, r) = (1e-5, self.fillet(psi));
        let (p, m) = (self.fillet(psi + e), self.fillet(psi - e));
        [r, (p - m) / (2.0 * e), (p - 2.0 * r + m) / (e * e)]
    }

    fn junctions(&self) -> Vec<f64> {
        let (s, t) = (self.period(), self.tangent());
        (0..self.polygon.sides).flat_map(|j| [s * j as f64 - t, s * j as f64 + t]).collect()
    }
}
