//! One sector of the exact model's section, each bin's radius found on the
//! pass itself instead of on a polyline through it.
//!
//! The tip's radius |P(a)|² = X0² + R1² − 2·X0·R1·cos(GR·a) grows with |a|
//! inside the pass, so the section's radius on a ray is the tip's radius at
//! the crossing of that ray (modulo the sector) nearest to a = 0. Walking out
//! from a = 0 on each side, each bin's crossing is solved for (bracketed
//! Newton on the polar angle, bins taken in the order the pass meets them),
//! and a side stops once it has crossed every bin's ray (or reached the
//! stock): later crossings are further out. [`Section::ideal`](super::Section::ideal) samples the pass
//! at 0.5 µm and interpolates linearly between samples: the bins here are
//! the limit of that as the samples get finer (a ten times finer polyline
//! agrees to ~1e-13 mm), within its interpolation error of them (≤ 1e-7 mm
//! for R2 = 10 mm over the planner's range), at a few hundred evaluations
//! of P where `ideal` makes up to 400 000.

use super::{Envelope, Setup};
use std::f64::consts::TAU;

/// Largest polar-angle change of one step, rad: keeps each step's angle
/// well inside (−π, π) and its polar angle close to linear in `a`.
const MAX_TURN: f64 = 0.05;

/// The pass's tip, its velocity and the sign of its polar angle's rate.
#[derive(Clone, Copy)]
struct Point {
    a: f64,
    x: f64,
    y: f64,
    /// x·y' − y·x' = r²·dθ/da
    cross: f64,
}

struct Pass {
    x0: f64,
    r1: f64,
    k: f64,
    /// s·GR, the cutter's turn per work turn (with sign)
    sgr: f64,
}

impl Pass {
    /// |P(a)|: |X0 − R1·e^{iθ}| with θ = s·GR·a.
    fn radius(&self, a: f64) -> f64 {
        let half = (0.5 * self.sgr * a).sin();
        ((self.x0 - self.r1).powi(2) + 4.0 * self.x0 * self.r1 * half * half).sqrt()
    }

    fn at(&self, a: f64) -> Point {
        // As Setup::tip: e^{−ia}·(X0 − R1·e^{iθ}), θ = s·GR·a.
        let (sn, cs) = (a - self.sgr * a).sin_cos();
        let (sa, ca) = a.sin_cos();
        let (x, y) = (self.x0 * ca - self.r1 * cs, -self.x0 * sa + self.r1 * sn);
        // a − θ = −k·a
        let (dx, dy) = (-self.x0 * sa - self.r1 * self.k * sn, -self.x0 * ca - self.r1 * self.k * cs);
        Point { a, x, y, cross: x * dy - y * dx }
    }
}

/// Signed angle from direction `(c, s)` to the point.
fn angle_from(p: &Point, c: f64, s: f64) -> f64 {
    (c * p.y - s * p.x).atan2(c * p.x + s * p.y)
}

/// Signed angle from `p` to `q` (|·| < π).
fn turn(p: &Point, q: &Point) -> f64 {
    (p.x * q.y - p.y * q.x).atan2(p.x * q.x + p.y * q.y)
}

/// The sector envelope (start −π/N, period 2π/N, `bins` bins) of the pass
/// of `setup`, capped by the stock.
pub fn sector_envelope(setup: &Setup, bins: usize) -> Envelope {
    let n = setup.sides().max(1);
    let sector = TAU / n as f64;
    let mut env = Envelope::new(-sector / 2.0, sector, sector, bins, setup.stock_radius_mm);
    let w = setup.pass_half_window();
    if !(w > 0.0 && w.is_finite()) {
        return env;
    }
    let pass = Pass {
        x0: setup.centre_distance(),
        r1: setup.cutter_radius_mm,
        k: setup.k(),
        sgr: setup.direction.sign() * setup.gr(),
    };
    // Phase step of the faster of e^{−ia} and e^{ika}.
    let base = (0.02 / setup.k().abs().max(1.0)).min(w / 8.0);
    for side in [1.0, -1.0] {
        walk(&pass, &mut env, side * w, base);
    }
    env
}

/// Walks from a = 0 to a = `end`, lowering every bin the pass crosses.
fn walk(pass: &Pass, env: &mut Envelope, end: f64, base: f64) {
    let mut hit = Hits { seen: vec![false; env.bins()], count: 0 };
    let mut p0 = pass.at(0.0);
    let mut t0 = p0.y.atan2(p0.x);
    let mut da = base;
    while p0.a != end && hit.count < hit.seen.len() {
        let a1 = if (end - p0.a).abs() <= da { end } else { p0.a + da.copysign(end) };
        let p1 = pass.at(a1);
        let dt = turn(&p0, &p1);
        if dt.abs() > MAX_TURN && da > end.abs() * 1e-14 {
            da *= 0.5;
            continue;
        }
        let t1 = t0 + dt;
        if (p0.cross > 0.0) != (p1.cross > 0.0) && p0.cross != 0.0 && p1.cross != 0.0 {
            // The polar angle turns back inside the step: split it there.
            let pm = turning_point(pass, p0, p1);
            let tm = t0 + turn(&p0, &pm);
            cross_bins(pass, env, &mut hit, p0, t0, pm, tm);
            cross_bins(pass, env, &mut hit, pm, tm, p1, t1);
        } else {
            cross_bins(pass, env, &mut hit, p0, t0, p1, t1);
        }
        (p0, t0) = (p1, t1);
        if dt.abs() < MAX_TURN / 4.0 {
            da = (da * 2.0).min(base);
        }
    }
}

/// Where r²·dθ/da changes sign between `p` and `q` (bisection).
fn turning_point(pass: &Pass, mut p: Point, mut q: Point) -> Point {
    for _ in 0..200 {
        let mid = 0.5 * (p.a + q.a);
        if mid == p.a || mid == q.a {
            break;
        }
        let m = pass.at(mid);
        if (m.cross > 0.0) == (p.cross > 0.0) {
            p = m
        } else {
            q = m
        }
    }
    p
}

/// Lowers the bins whose rays (θ unwrapped, any period) lie between polar
/// angles `ta` at `pa` and `tb` at `pb`, the angle being monotonic between
/// them and `pa` the nearer to a = 0. Rays are taken from `pa` on, so the
/// first crossing of each bin on this side is the one solved for; `hit`
/// marks the bins crossed so far (later crossings are further out).
fn cross_bins(pass: &Pass, env: &mut Envelope, hit: &mut Hits, pa: Point, ta: f64, pb: Point, tb: f64) {
    // A ray through an end (the pass's end, or a piece's) counts as crossed.
    let slack = 1e-12 * env.period;
    let (lo, hi) = if ta <= tb { (ta - slack, tb + slack) } else { (tb - slack, ta + slack) };
    let (start, period, step, bins) = (env.start, env.period, env.step(), env.bins() as i64);
    let (first, last) = (((lo - start) / step).ceil() as i64, ((hi - start) / step).floor() as i64);
    if last < first {
        return;
    }
    let r_near = pa.x.hypot(pa.y);
    for n in 0..=(last - first) {
        let j = if ta <= tb { first + n } else { last - n };
        let (m, i) = (j.div_euclid(bins), j.rem_euclid(bins) as usize);
        if hit.seen[i] {
            continue;
        }
        hit.seen[i] = true;
        hit.count += 1;
        if env.radius[i] > r_near {
            // every crossing from `pa` on is at least `r_near` out
            let t = start + step * i as f64 + m as f64 * period;
            let r = crossing_radius(pass, pa, ta, pb, tb, t);
            if r < env.radius[i] {
                env.radius[i] = r;
            }
        }
        if hit.count == hit.seen.len() {
            return;
        }
    }
}

/// The bins one side of the pass has crossed.
struct Hits {
    seen: Vec<bool>,
    count: usize,
}

/// |P(a)| where the polar angle θ(a) = t, θ monotonic from `ta` at `pa` to
/// `tb` at `pb`: bracketed Newton from a cubic (Hermite) guess.
fn crossing_radius(pass: &Pass, pa: Point, ta: f64, pb: Point, tb: f64, t: f64) -> f64 {
    let (c, s) = (t.cos(), t.sin());
    // g(a) = θ(a) − t, ≤ 0 at `below`, ≥ 0 at `above`
    let (mut below, mut above) = if ta <= tb { (pa.a, pb.a) } else { (pb.a, pa.a) };
    let mut a = guess(pa, ta, pb, tb, t);
    let piece = (pb.a - pa.a).abs();
    for _ in 0..100 {
        let p = pass.at(a);
        let g = angle_from(&p, c, s);
        if g == 0.0 {
            break;
        }
        if g < 0.0 {
            below = a
        } else {
            above = a
        }
        let newton = a - g * (p.x * p.x + p.y * p.y) / p.cross;
        let (l, h) = if below <= above { (below, above) } else { (above, below) };
        if newton > l && newton < h {
            let step = (newton - a).abs();
            a = newton;
            if step <= 1e-7 * piece {
                // converging quadratically: the error left is ~(this step)²/piece
                break;
            }
        } else {
            a = 0.5 * (l + h);
        }
        if h - l <= 4.0 * f64::EPSILON * h.abs().max(l.abs()) {
            break;
        }
    }
    pass.radius(a)
}

/// Where θ(a) = t, from the ends' angles and rates (cubic Hermite in t),
/// or linear where a rate is near 0 (a turning point at that end).
fn guess(pa: Point, ta: f64, pb: Point, tb: f64, t: f64) -> f64 {
    let dt = tb - ta;
    if dt == 0.0 {
        return pa.a;
    }
    let u = ((t - ta) / dt).clamp(0.0, 1.0);
    let linear = pa.a + (pb.a - pa.a) * u;
    // da/ds at the ends, s = (t − ta)/dt ∈ [0, 1]
    let slope = |p: &Point| dt * (p.x * p.x + p.y * p.y) / p.cross;
    let (m0, m1, chord) = (slope(&pa), slope(&pb), pb.a - pa.a);
    if !(m0 / chord > 0.25 && m0 / chord < 4.0 && m1 / chord > 0.25 && m1 / chord < 4.0) {
        return linear;
    }
    let (u2, u3) = (u * u, u * u * u);
    let cubic =
        (2.0 * u3 - 3.0 * u2 + 1.0) * pa.a + (u3 - 2.0 * u2 + u) * m0 + (-2.0 * u3 + 3.0 * u2) * pb.a + (u3 - u2) * m1;
    let (l, h) = if pa.a <= pb.a { (pa.a, pb.a) } else { (pb.a, pa.a) };
    if cubic >= l && cubic <= h {
        cubic
    } else {
        linear
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Direction, Section, Setup};
    use polyturn_sync::Ratio;

    /// Setups over the planner's range: N flats from r turns of a Z-edged
    /// cutter, fast and slow ratios, both senses, small to large cutters,
    /// shallow to deep cuts (R2 = 10 mm).
    fn planner_like_setups() -> Vec<Setup> {
        let shapes =
            [(2, 1, 1), (2, 11, 12), (2, 3, 4), (3, 1, 1), (3, 2, 5), (3, 11, 12), (6, 1, 3), (7, 5, 3), (13, 12, 12)];
        let more = [(1000, 1, 1), (1000, 3, 7), (997, 12, 12)];
        let mut out = Vec::new();
        for (j, &(sides, revs, edges)) in shapes.iter().chain(&more).enumerate() {
            for (l, direction) in [Direction::Same, Direction::Opposite].into_iter().enumerate() {
                for m in 0..2 {
                    let r1 = [5.0, 12.5, 50.0, 1000.0][(j + l + 2 * m) % 4];
                    let doc = [0.01, 1.5, 4.0, 9.0][(j + 3 * l + m) % 4];
                    let ratio = Ratio::new(sides, revs * edges).unwrap();
                    out.push(Setup {
                        cutter_radius_mm: r1,
                        stock_radius_mm: 10.0,
                        depth_mm: doc,
                        ratio,
                        edges: edges as u32,
                        direction,
                    });
                }
            }
        }
        out
    }

    /// The simulator's ideal (`Section::ideal_tiled`) is the sampled one.
    #[test]
    fn the_whole_circle_tiled_from_the_solved_sector_matches_the_sampled_section() {
        for s in planner_like_setups() {
            let bins = 128;
            let (a, b) = (Section::ideal(&s, bins), Section::ideal_tiled(&s, bins));
            assert_eq!(b.envelope.bins(), a.envelope.bins());
            for (i, (x, y)) in a.envelope.radius.iter().zip(&b.envelope.radius).enumerate() {
                assert!((x - y).abs() <= 1e-7, "{s:?} bin {i}: {x} vs {y}");
            }
            assert_eq!((a.envelope.start, a.envelope.span), (b.envelope.start, b.envelope.span));
        }
    }

    /// The sector solved on the pass against the 0.5 µm polyline, bin by bin:
    /// they differ by the polyline's interpolation alone (the solved bins
    /// match a ten times finer polyline to ~1e-13 mm).
    #[test]
    fn the_sector_solved_on_the_pass_matches_the_sampled_section() {
        for s in planner_like_setups() {
            let bins = 128;
            let (a, b) = (Section::ideal(&s, bins), Section::ideal_sector(&s, bins));
            assert_eq!(b.envelope.bins(), bins);
            for i in 0..bins {
                let (x, y) = (a.envelope.radius[i], b.envelope.radius[i]);
                assert!((x - y).abs() <= 1e-7, "{s:?} bin {i}: {x} vs {y}");
            }
            let (fa, fb) = (a.summary().flat_deviation, b.flat_deviation(0));
            assert!((fa - fb).abs() <= 1e-7, "{s:?}: flat {fa} vs {fb}");
            assert_eq!(a.summary().corners_sharp, b.corner_radius(0) < 10.0 - 1e-9, "{s:?}");
        }
    }
}
