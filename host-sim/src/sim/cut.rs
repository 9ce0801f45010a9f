//! Cuts the section from recorded motion: at every tick the lathe's and the
//! cutter's real angles; between ticks both are interpolated and the tip is
//! sampled finely while it is inside the stock. Same model as `geometry`.

use crate::geometry::{Envelope, Section, Setup};
use std::f64::consts::{PI, TAU};

pub struct CutRecorder {
    setup: Setup,
    env: Envelope,
    /// half-width of the in-stock window of the tip angle, rad
    window: f64,
    last: Option<(f64, f64, f64)>,
    pub passes_cut: u64,
    /// the points of the segment being cut (kept: one allocation a run,
    /// not one a tick)
    points: Vec<(f64, f64)>,
    /// the last angles' (sin, cos), the work's and the tip's against it: a
    /// tick's end is the next tick's start, and every edge's segment
    /// shares the work's
    turned: [(f64, (f64, f64)); 4],
}

/// (sin, cos) of an angle a piece of the path turns by: the Taylor series
/// to x⁷ (within 1e-15 below 0.05 rad, the pieces' angles), else the
/// library's.
fn small_sin_cos(x: f64) -> (f64, f64) {
    if x.abs() >= 0.05 {
        return x.sin_cos();
    }
    let x2 = x * x;
    let s = x * (1.0 - x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0))));
    let c = 1.0 - x2 * 0.5 * (1.0 - x2 * (1.0 / 12.0) * (1.0 - x2 * (1.0 / 30.0)));
    (s, c)
}

/// Largest straight piece of a sampled tip path, mm. The tip path's radius
/// of curvature is ≳ 5 mm, so a 50 µm chord strays (0.05)²/(8·5) ≈ 0.06 µm.
const PIECE_MM: f64 = 0.05;

impl CutRecorder {
    pub fn new(setup: &Setup, bins_per_side: usize) -> CutRecorder {
        let n = setup.sides().max(1) as usize;
        let start = -PI / n as f64;
        CutRecorder {
            setup: *setup,
            env: Envelope::new(start, TAU, TAU, n * bins_per_side, setup.stock_radius_mm),
            window: setup.in_stock_cos().acos(),
            last: None,
            passes_cut: 0,
            points: Vec::new(),
            turned: [(f64::NAN, (0.0, 1.0)); 4],
        }
    }

    /// Forgets the previous sample (the cut pauses: not synchronised).
    pub fn pause(&mut self) {
        self.last = None;
    }

    /// Records the state at one tick: work angle `a`, cutter angle `theta`,
    /// and the X axis's change of centre distance `dx` (mm; 0 without one).
    pub fn record(&mut self, a: f64, theta: f64, dx: f64) {
        if let Some((a0, t0, x0)) = self.last.replace((a, theta, dx)) {
            for j in 0..self.setup.edges {
                let edge = TAU * j as f64 / self.setup.edges as f64;
                self.segment(a0, t0 + edge, a, theta + edge, (x0, dx));
            }
        }
    }

    /// Whether the tip angle passes within the in-stock window (around a
    /// multiple of 2π) between `p0` and `p1`: no trigonometry, one floor.
    fn in_stock(&self, p0: f64, p1: f64) -> bool {
        let (lo, hi) = if p0 <= p1 { (p0, p1) } else { (p1, p0) };
        let w = self.window;
        // the nearest multiple of 2π at or above lo − w must not pass hi + w
        // (× 1/2π, not ÷ 2π: a division's latency a tick an edge; an ulp at
        // the window's edge decides only for a path that grazes the stock's
        // surface, which cuts nothing)
        let k = crate::round::ceil((lo - w) * (1.0 / TAU));
        k * TAU <= hi + w
    }

    fn segment(&mut self, a0: f64, p0: f64, a1: f64, p1: f64, (dx0, dx1): (f64, f64)) {
        if !self.in_stock(p0, p1) {
            return;
        }
        // Both angles are linear in i, so their phasors turn by a constant
        // step: `tip_at` = X0·e^{−ia} − R1·e^{−i(a−θ)}, without trig per point
        // (the ends' phasors give the ends' points, `Setup::tip_of`).
        let (x0c, r1) = (self.setup.centre_distance(), self.setup.cutter_radius_mm);
        let (ua, ua1) = (a0 - p0, a1 - p1);
        let (mut ea, mut eu) = (self.sin_cos(a0), self.sin_cos(ua));
        let (x0, y0) = self.setup.tip_of(ea, eu);
        let (ea1, eu1) = (self.sin_cos(a1), self.sin_cos(ua1));
        let (x1, y1) = self.setup.tip_of(ea1, eu1);
        let pieces = crate::round::ceil((x1 - x0).hypot(y1 - y0) / PIECE_MM);
        let ddx = (dx1 - dx0) / pieces.clamp(1.0, 4096.0);
        let n = (pieces as usize).clamp(1, 4096);
        let ub = (ua1 - ua) / n as f64;
        let (da, du) = (small_sin_cos((a1 - a0) / n as f64), small_sin_cos(ub));
        let turn = |(s, c): (f64, f64), (ds, dc): (f64, f64)| (s * dc + c * ds, c * dc - s * ds);
        // (squared: no `hypot` a point, and a point on the bound cuts nothing)
        let limit2 = (self.setup.stock_radius_mm * 1.05).powi(2);
        let mut pts = std::mem::take(&mut self.points);
        pts.clear();
        for i in 0..=n {
            let xc = x0c + dx0 + ddx * i as f64;
            let p = (xc * ea.1 - r1 * eu.1, -xc * ea.0 + r1 * eu.0);
            if p.0 * p.0 + p.1 * p.1 < limit2 {
                pts.push(p);
            }
            ea = turn(ea, da);
            eu = turn(eu, du);
        }
        if pts.len() > 1 {
            self.passes_cut += 1;
            self.env.add_polyline(&pts);
        }
        self.points = pts;
    }

    /// (sin, cos) of `a`, from the last four if it is one of them
    /// (exactly: the same f64).
    fn sin_cos(&mut self, a: f64) -> (f64, f64) {
        if let Some(&(_, sc)) = self.turned.iter().find(|e| e.0 == a) {
            return sc;
        }
        let sc = a.sin_cos();
        self.turned.rotate_left(1);
        self.turned[3] = (a, sc);
        sc
    }

    pub fn section(&self) -> Section {
        Section {
            sides: self.setup.sides(),
            stock_radius: self.setup.stock_radius_mm,
            envelope: self.env.clone(),
            periodic: false,
        }
    }
}

#[cfg(test)]
mod series_tests {
    use super::small_sin_cos;

    #[test]
    fn the_pieces_series_is_the_librarys_sine_and_cosine() {
        for k in -1_000..=1_000 {
            let x = k as f64 * 0.0001; // to ±0.1: the series below 0.05
            let ((s, c), (ls, lc)) = (small_sin_cos(x), x.sin_cos());
            assert!((s - ls).abs() <= 1e-15 && (c - lc).abs() <= 1e-15, "{x}: {s} {c} against {ls} {lc}");
        }
    }
}
