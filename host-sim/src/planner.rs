//! The setup planner: every (ratio, edges, direction) that cuts N flats,
//! with what a machinist needs to choose between them.

use crate::geometry::roundness::ROUND_FRACTION;
use crate::geometry::{Direction, Refusal, Roundness, Section, SectionSummary, Setup, SetupError, LENGTH_MM};
use polyturn_sync::ratio::gcd;
use polyturn_sync::Ratio;
use std::collections::HashMap;

#[derive(Clone, Debug, serde::Serialize)]
pub struct Candidate {
    pub ratio: String,
    pub edges: u32,
    pub direction: &'static str,
    pub revolutions: u32,
    pub depth: f64,
    pub flat_deviation: f64,
    pub corners_sharp: bool,
    pub cutter_rpm: Option<f64>,
    /// Ghionea eq. (3), (4) (opposite sense) or their internal-rolling
    /// counterparts (same sense); null where infinite (same sense, 1:1)
    pub rolling_radius_work: Option<f64>,
    pub rolling_radius_cutter: Option<f64>,
    /// peak tip speed relative to the work inside the cut, m/s (eq. 5)
    pub peak_tip_speed: Option<f64>,
    /// smallest cutter radius keeping |flat deviation| ≤ tolerance, mm
    pub min_cutter_radius: Option<f64>,
}

pub struct Request {
    pub sides: u32,
    pub stock_radius: f64,
    pub depth: f64,
    pub cutter_radius: Option<f64>,
    pub max_edges: u32,
    pub max_ratio: f64,
    pub max_revolutions: u32,
    pub rpm: Option<f64>,
    pub tolerance: f64,
}

/// Cutter radius used for the figures when none is given: 5 × stock,
/// Foale's examples' proportion (50 mm cutter, 10 mm work), as the
/// shortest decimal a machinist would type for it: 5 x a radius given in
/// decimals is not exact in binary (1.1500000000000001 for 5 x 0.23), and
/// the lines printed to reproduce a row would carry it. 12 significant
/// figures lie far below any length the tools measure.
pub fn default_cutter(stock: f64) -> f64 {
    let r = 5.0 * stock;
    format!("{r:.11e}").parse().unwrap_or(r)
}

/// What the planner found: the setups that cut the polygon, flattest
/// first, and how many more it left out because `geometry` refuses them
/// (`Setup::check`): as nearly round, or for a value out of its range.
pub struct Plan {
    pub found: Vec<Candidate>,
    pub round: usize,
    /// each value refused, once, with how many setups it left out
    pub refused: Vec<(SetupError, usize)>,
}

impl Plan {
    fn leave_out(&mut self, why: Refusal) {
        match why {
            Refusal::Round(_) => self.round += 1,
            Refusal::Setting(e) => match self.refused.iter_mut().find(|(seen, _)| *seen == e) {
                Some((_, n)) => *n += 1,
                None => self.refused.push((e, 1)),
            },
        }
    }
}

pub fn plan(req: &Request) -> Plan {
    let r1 = req.cutter_radius.unwrap_or_else(|| default_cutter(req.stock_radius));
    let mut out = Plan { found: Vec::new(), round: 0, refused: Vec::new() };
    // The section depends on the ratio and the sense but not on the edges:
    // it is one tip's pass and its N rotations, N = `sides` for every
    // candidate. Candidates whose r·Z is the same product share the ratio
    // N/(r·Z) (2/3 × 3 edges in 1 turn, 2/3 × 1 edge over 3 turns), so
    // their figures are computed once.
    let mut figures: HashMap<(Ratio, bool), Result<Figures, Refusal>> = HashMap::new();
    for edges in 1..=req.max_edges {
        for revs in 1..=req.max_revolutions {
            // GR·Z = N/r  →  GR = N/(r·Z), with gcd(N, r) = 1 so that N flats
            // (not fewer) come out over r turns.
            if gcd(req.sides as u64, revs as u64) != 1 {
                continue;
            }
            let Ok(ratio) = Ratio::new(req.sides as u64, (revs * edges) as u64) else { continue };
            if ratio.to_f64() > req.max_ratio || ratio.pattern(edges) != (req.sides, revs) {
                continue;
            }
            for direction in [Direction::Same, Direction::Opposite] {
                let setup = Setup {
                    cutter_radius_mm: r1,
                    stock_radius_mm: req.stock_radius,
                    depth_mm: req.depth,
                    ratio,
                    edges,
                    direction,
                };
                // `geometry`'s check, once per shared section; the values
                // that vary between the candidates sharing it (the edges)
                // checked for each
                let judged = setup.validate().map_err(Refusal::Setting).and_then(|()| {
                    figures
                        .entry((ratio, direction == Direction::Same))
                        .or_insert_with(|| Figures::of(&setup, req))
                        .clone()
                });
                match judged {
                    Ok(f) => out.found.push(candidate(&setup, req, f)),
                    Err(why) => out.leave_out(why),
                }
            }
        }
    }
    out.found.sort_by(|a, b| {
        let flat = |c: &Candidate| (c.flat_deviation.abs() * 1e4).round() as i64; // 0.1 µm bins
        flat(a)
            .cmp(&flat(b))
            .then(a.cutter_rpm.partial_cmp(&b.cutter_rpm).unwrap_or(std::cmp::Ordering::Equal))
            .then(a.revolutions.cmp(&b.revolutions))
    });
    out
}

/// What a candidate's section tells: flatness, corners, smallest cutter.
#[derive(Clone, Copy)]
struct Figures {
    flat_deviation: f64,
    corners_sharp: bool,
    min_cutter_radius: Option<f64>,
}

impl Figures {
    /// The figures `geometry` prints for a setup it takes
    /// (`Setup::summary`), else why it refuses it.
    fn of(setup: &Setup, req: &Request) -> Result<Figures, Refusal> {
        let s = setup.summary()?;
        let min_cutter_radius = if req.cutter_radius.is_none() { min_cutter(setup, req.tolerance) } else { None };
        Ok(Figures { flat_deviation: s.flat_deviation, corners_sharp: s.corners_sharp, min_cutter_radius })
    }
}

fn candidate(setup: &Setup, req: &Request, f: Figures) -> Candidate {
    let rolling = setup.rolling_radii();
    let w = setup.pass_half_window();
    let peak = (0..=64).map(|i| setup.relative_speed_factor(-w + 2.0 * w * i as f64 / 64.0)).fold(0.0, f64::max);
    Candidate {
        ratio: setup.ratio.to_string(),
        edges: setup.edges,
        direction: setup.direction.name(),
        revolutions: setup.pattern().1,
        depth: setup.depth_mm,
        flat_deviation: f.flat_deviation,
        corners_sharp: f.corners_sharp,
        cutter_rpm: req.rpm.map(|r| r * setup.gr()),
        rolling_radius_work: rolling.map(|r| r.0),
        rolling_radius_cutter: rolling.map(|r| r.1),
        // mm per rad × rad/s → mm/s → m/s
        peak_tip_speed: req.rpm.map(|r| peak * r / 60.0 * std::f64::consts::TAU / 1000.0),
        min_cutter_radius: f.min_cutter_radius,
    }
}

/// The largest cutter `min_cutter` tries, as a multiple of the stock
/// radius (`setups` names it where it finds none).
pub const MIN_CUTTER_SCAN: f64 = 100.0;

/// The largest cutter radius `min_cutter` tries for stock of radius `r2`:
/// [`MIN_CUTTER_SCAN`] times it, or the largest `geometry` takes.
pub fn min_cutter_scan_top(r2: f64) -> f64 {
    (r2 * MIN_CUTTER_SCAN).min(LENGTH_MM.1)
}

/// `geometry`'s flat deviation of `setup` with cutter radius `r1` (the
/// one computation it prints: `Setup::summary`), None where it refuses it.
fn deviation(setup: &Setup, r1: f64) -> Option<f64> {
    Setup { cutter_radius_mm: r1, ..*setup }.summary().ok().map(|s| s.flat_deviation)
}

/// Whether `geometry` takes `setup` with cutter radius `r1` and finds its
/// flats within `tol`.
fn meets(setup: &Setup, r1: f64, tol: f64) -> bool {
    deviation(setup, r1).is_some_and(|d| d.abs() <= tol)
}

/// The scan's finest step, each radius 2 % over the last: where the
/// flats are near the tolerance, or their trend is not known.
const SCAN_STEP: f64 = 1.02;

/// The scan's longest step, 10 %: where the flats are far from the
/// tolerance and change slowly with the radius.
const LONGEST_STEP: f64 = 1.1;

/// The scan's step where there is no estimate, 25 %: a nearly round
/// section, which `geometry` refuses (the last such step is read again
/// finely when a section comes out of it).
const ROUND_STEP: f64 = 1.25;

/// The scan's next step from radius `r`, whose estimate is `est`, the last
/// being `prev`: as far as the trend between them (linear in ln R1) would
/// take the deviation half way to the tolerance, from 2 % to 10 %;
/// [`ROUND_STEP`] where there is no estimate. A band the scan
/// steps over without a zero crossing is one the deviation reaches
/// against its trend, within the step.
fn scan_step(prev: Option<(f64, f64)>, r: f64, est: Option<f64>, tol: f64) -> f64 {
    let Some(d) = est else { return ROUND_STEP };
    let Some((r0, d0)) = prev else { return SCAN_STEP };
    let room = 0.5 * (d.abs() - tol);
    let slope = ((d - d0) / (r / r0).ln()).abs();
    if room <= 0.0 || (d > 0.0) != (d0 > 0.0) {
        return SCAN_STEP;
    }
    (room / slope).exp().clamp(SCAN_STEP, LONGEST_STEP)
}

/// Where the estimate is within the tolerance but `geometry` is not, the
/// next radius `geometry` is asked about is at least this much larger (a
/// long stretch of such radii would otherwise cost a `geometry` each).
const CHECK_STRIDE: f64 = 1.1;

/// The scan's estimate of the flat deviation with cutter radius `r1`: one
/// sector at [`ESTIMATE_BINS`] bins, some 20 to 50 times cheaper than
/// `geometry`'s section. With sharp corners it is `geometry`'s figure to
/// 0.05 µm (0.2 µm where the flats are 2 mm out; measured for 3 to 12
/// sides, R2 1 to 100 mm). With round ones each flat's ends are found to
/// a coarser bin and it comes out mostly smaller, so that it finds the
/// bands `geometry` has and some it has not, which `geometry` then judges.
/// None where a flat is narrower than two bins (no chord), or where
/// `Roundness` finds the section nearly round: `geometry` refuses it.
fn estimate(setup: &Setup, r1: f64) -> Option<f64> {
    let setup = Setup { cutter_radius_mm: r1, ..*setup };
    let section = Section::ideal_sector(&setup, ESTIMATE_BINS);
    let r = &section.envelope.radius;
    // what `Roundness` reads, from the one sector every flat repeats
    let s = SectionSummary {
        sides: section.sides,
        inscribed_radius: r.iter().copied().fold(f64::INFINITY, f64::min),
        circumscribed_radius: r.iter().copied().fold(0.0, f64::max),
        across_flats: None,
        flat_deviation: section.flat_deviation(0),
        corners_sharp: false,
    };
    // one or two flats are judged by their relief, which the coarser bins
    // find less of: a margin, so that none `geometry` takes is left out
    let margin = if section.sides <= 2 { 0.05 } else { 0.0 };
    let round = Roundness::of(&s, setup.depth_mm).fraction > ROUND_FRACTION + margin;
    Some(s.flat_deviation).filter(|d| !round && *d != 0.0 && d.is_finite())
}

/// Bins per flat of [`estimate`]'s sector (`geometry`'s: up to 4096).
const ESTIMATE_BINS: usize = 128;

/// The smallest cutter radius that `geometry` takes with flats within
/// `tol`, from just over the depth up to [`min_cutter_scan_top`], rounded
/// up to 3 significant figures (a size to make, printed whole; more
/// figures where the band of good radii is narrower than that). Below the
/// depth `geometry` refuses every radius (`Setup::validate`), and just
/// over it most sections are refused as nearly round ("too small for this
/// depth"): the scan starts there, and `geometry` judges each radius.
///
/// The flat deviation is not monotonic in the radius: it changes sign (a
/// small cutter's flats bulge, a larger one's are hollow), so there may be
/// a band of good cutters far below the radius where it creeps back within
/// `tol`. The scan reads the estimate from the bottom up, and stops at the
/// first band `geometry` confirms. Its steps, relative to R1: 2 % where
/// the flats are near `tol` or their trend is not known; longer, up to
/// 10 %, where the trend keeps them far from it ([`scan_step`]); 25 %
/// where a section has no estimate (nearly round), the last such step read
/// again at 2 % when a section comes out of it. What it can miss: a band
/// where the deviation crosses zero is found however narrow (it is
/// bisected for), unless it crosses back within the same step; a band
/// where it only dips within `tol` is missed if narrower than the step
/// there, 2 % of R1 near `tol` (0.06 mm at R1 = 3 mm, 0.3 mm at 15 mm);
/// and where the estimate is within `tol` and `geometry` is not (round
/// corners), a band of `geometry`'s narrower than 10 % ([`CHECK_STRIDE`]).
fn min_cutter(setup: &Setup, tol: f64) -> Option<f64> {
    let (bottom, top) = (scan_bottom(setup), min_cutter_scan_top(setup.stock_radius_mm));
    let mut scan = Scan { bottom, top, last: bottom, prev: None, next_check: bottom, fine_until: bottom };
    let mut r = bottom;
    loop {
        let est = estimate(setup, r);
        if est.is_some() && scan.prev.is_none() && r > scan.fine_until && r > scan.last * SCAN_STEP * (1.0 + 1e-9) {
            // out of a stretch with no estimate by a long step: read the
            // step again finely, in case a band starts where it ends
            scan.fine_until = r;
            r = scan.last * SCAN_STEP;
            continue;
        }
        if let Some(found) = scan.band(setup, tol, r, est) {
            return Some(found);
        }
        if r >= top {
            return None;
        }
        let step = if r < scan.fine_until { SCAN_STEP } else { scan_step(scan.prev, r, est, tol) };
        (scan.last, scan.prev) = (r, est.map(|e| (r, e)));
        r = (r * step).min(top);
    }
}

/// Where [`min_cutter`]'s scan is.
struct Scan {
    bottom: f64,
    top: f64,
    /// the radius it read last
    last: f64,
    /// that radius and its estimate, where it has one
    prev: Option<(f64, f64)>,
    /// where the estimate is within the tolerance and `geometry` was not,
    /// the least radius it asks `geometry` about again
    next_check: f64,
    /// where it reads a stretch again finely, up to where
    fine_until: f64,
}

impl Scan {
    /// The smallest cutter `geometry` takes in the band the estimate finds
    /// between the last radius and `r` (whose estimate is `est`), if any.
    fn band(&mut self, setup: &Setup, tol: f64, r: f64, est: Option<f64>) -> Option<f64> {
        let (lo, bottom) = (self.last, self.bottom);
        match (est, self.prev) {
            (Some(e), _) if e.abs() <= tol && (r >= self.next_check || entering(self.prev, tol)) => {
                let within = match entering(self.prev, tol) {
                    true => least(setup, tol, lo, r, bottom),
                    false => meets(setup, r, tol).then(|| least_taken(setup, tol, lo, r, bottom)),
                };
                self.next_check = (r * CHECK_STRIDE).min(self.top);
                within
            }
            (Some(e), Some((lo, d_lo))) if (e > 0.0) != (d_lo > 0.0) => {
                crossing(setup, lo, d_lo, r, tol).and_then(|x| {
                    least(setup, tol, lo, x, bottom).or_else(|| {
                        geometry_crossing(setup, lo, r, tol).map(|g| least_taken(setup, tol, lo, g, bottom))
                    })
                })
            }
            _ => None,
        }
    }
}

/// Whether the estimate was out of `tol` (or none) at the last radius.
fn entering(prev: Option<(f64, f64)>, tol: f64) -> bool {
    prev.is_none_or(|(_, d)| d.abs() > tol)
}

/// The first radius the scan tries: just over the depth (a cutter whose
/// radius does not exceed it would have its axis inside the bar,
/// `Setup::validate`), and no smaller than `geometry` takes.
fn scan_bottom(setup: &Setup) -> f64 {
    (setup.depth_mm * 1.001).max(LENGTH_MM.0)
}

/// The least radius in (`lo`, `hi`] that `geometry` takes within `tol`,
/// where the estimate is within it at `hi` and not at `lo`, rounded up to
/// 3 figures; None if `geometry` does not take `hi`. The estimate's edge
/// first, rounded: where `geometry` takes it and not the 3-figure size
/// under it (the estimate near its figure), two of `geometry`'s sections
/// tell it.
fn least(setup: &Setup, tol: f64, lo: f64, hi: f64, bottom: f64) -> Option<f64> {
    let within = |r: f64| estimate(setup, r).is_some_and(|d| d.abs() <= tol);
    let edge = round_up_3(bisect(lo, hi, 12, within));
    if !meets(setup, edge, tol) {
        // `geometry`'s edge is over the estimate's
        return meets(setup, hi, tol).then(|| least_taken(setup, tol, edge, hi, bottom));
    }
    let mut size = edge;
    for _ in 0..3 {
        let under = round_down_3(size);
        if !meets(setup, under, tol) {
            return Some(size);
        }
        size = under;
    }
    Some(least_taken(setup, tol, lo.min(size), size, bottom))
}

/// The least radius `geometry` takes within `tol` below `hi`, which it
/// takes, down to `bottom`, by `geometry`'s figure alone: stepped down
/// while the radius `lo` under it is taken too, then bisected; rounded up
/// to 3 figures where that is still taken, else to as many as it needs.
fn least_taken(setup: &Setup, tol: f64, mut lo: f64, mut hi: f64, bottom: f64) -> f64 {
    let r = loop {
        if !meets(setup, lo, tol) {
            // 7 halvings of a 2 % step: 0.02 %, inside the rounding (0.1 %
            // at least); of a 10 % one, 0.08 %
            break bisect(lo, hi, 7, |mid| meets(setup, mid, tol));
        }
        if lo <= bottom {
            break lo;
        }
        hi = lo;
        lo = (lo / SCAN_STEP).max(bottom);
    };
    (3..=6).map(|figures| round_up(r, figures)).find(|&size| meets(setup, size, tol)).unwrap_or(r)
}

/// The least radius in (`lo`, `hi`] that `ok` takes, to `halvings`
/// bisections, where `ok(hi)` holds and `ok(lo)` does not.
fn bisect(mut lo: f64, mut hi: f64, halvings: u32, ok: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..halvings {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            hi = mid
        } else {
            lo = mid
        }
    }
    hi
}

/// A radius between `lo` (estimate `d_lo`, out of `tol`) and `hi` (out of
/// it on the other side) where the estimate is within `tol`: its zero
/// crossing, bisected for on its sign; None where it jumps across zero.
fn crossing(setup: &Setup, lo: f64, d_lo: f64, hi: f64, tol: f64) -> Option<f64> {
    zero_crossing(lo, d_lo, hi, tol, |r| estimate(setup, r))
}

/// Where the estimate crosses zero between `lo` and `hi` but `geometry`
/// does not take its crossing: `geometry`'s own, if its deviation changes
/// sign there too, and it takes that.
fn geometry_crossing(setup: &Setup, lo: f64, hi: f64, tol: f64) -> Option<f64> {
    let d_lo = deviation(setup, lo)?;
    deviation(setup, hi).filter(|d| (*d > 0.0) != (d_lo > 0.0))?;
    zero_crossing(lo, d_lo, hi, tol, |r| deviation(setup, r)).filter(|&x| meets(setup, x, tol))
}

/// A radius in (`lo`, `hi`) where `dev` is within `tol`, bisected for on
/// its sign from `lo` (where it is `d_lo`); None if `dev` has none there
/// on the way.
fn zero_crossing(mut lo: f64, d_lo: f64, mut hi: f64, tol: f64, dev: impl Fn(f64) -> Option<f64>) -> Option<f64> {
    // 24 halvings of a 2 % step: 1e-9 of the radius
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        let d = dev(mid)?;
        if d.abs() <= tol {
            return Some(mid);
        }
        if (d > 0.0) == (d_lo > 0.0) {
            lo = mid
        } else {
            hi = mid
        }
    }
    None
}

/// The 3-figure size under `r`, itself of 3 figures: 12.6 under 12.7,
/// 99.9 under 100.
fn round_down_3(r: f64) -> f64 {
    let magnitude = (r * (1.0 - 1e-12)).log10().floor() as i32;
    let decimals = (2 - magnitude).max(0) as usize;
    format!("{:.decimals$}", r - 10f64.powi(magnitude - 2)).parse().unwrap_or(r)
}

/// `r` rounded up to 3 significant figures, as the nearest float to its
/// decimal (so it prints as those figures).
fn round_up_3(r: f64) -> f64 {
    round_up(r, 3)
}

/// `r` rounded up to `figures` significant figures, as the nearest float
/// to its decimal.
fn round_up(r: f64, figures: i32) -> f64 {
    let magnitude = r.log10().floor() as i32;
    let unit = 10f64.powi(magnitude - (figures - 1));
    let up = (r / unit).ceil() * unit;
    let decimals = (figures - 1 - magnitude).max(0) as usize;
    format!("{up:.decimals$}").parse().unwrap_or(r).max(r)
}

#[cfg(test)]
mod direct_tests;

#[cfg(test)]
mod tests {
    use super::*;

    fn req(sides: u32) -> Request {
        Request {
            sides,
            stock_radius: 10.0,
            depth: 1.5,
            cutter_radius: Some(50.0),
            max_edges: 6,
            max_ratio: 8.0,
            max_revolutions: 1,
            rpm: Some(300.0),
            tolerance: 0.01,
        }
    }

    #[test]
    fn a_hexagon_has_foales_four_integer_setups_in_each_sense() {
        let c = plan(&req(6)).found;
        // Foale: four integer-ratio options for a hexagon (and fractional
        // ones such as 3/2 × 4 that also finish in one turn).
        let mut pairs: Vec<(String, u32)> =
            c.iter().filter(|c| !c.ratio.contains('/')).map(|c| (c.ratio.clone(), c.edges)).collect();
        pairs.sort();
        pairs.dedup();
        assert_eq!(pairs, vec![("1".into(), 6), ("2".into(), 3), ("3".into(), 2), ("6".into(), 1)]);
        assert!(c.iter().any(|c| c.ratio == "3/2" && c.edges == 4 && c.revolutions == 1));
        // flattest first: 2:1 same sense is Foale's "nearly magic" choice
        assert_eq!((c[0].ratio.as_str(), c[0].direction), ("2", "same"));
        assert!(c
            .windows(2)
            .all(|w| (w[0].flat_deviation.abs() * 1e4).round() <= (w[1].flat_deviation.abs() * 1e4).round()));
    }

    #[test]
    fn a_prime_has_only_the_two_integer_setups_but_fractional_ones_over_turns() {
        // Foale: a prime needs 1:1 × N or N:1 × 1 among integer ratios.
        let c = plan(&req(7)).found;
        let integer = |c: &&Candidate| !c.ratio.contains('/');
        assert!(c.iter().filter(integer).all(|c| (c.ratio == "7" && c.edges == 1) || (c.ratio == "1" && c.edges == 7)));
        let mut r = req(11);
        r.max_revolutions = 3;
        r.max_edges = 3;
        assert!(plan(&r).found.iter().any(|c| c.ratio == "11/3" && c.edges == 1 && c.revolutions == 3));
        assert!(plan(&r).found.iter().any(|c| c.ratio == "11/3" && c.edges == 3 && c.revolutions == 1));
    }

    #[test]
    fn the_smallest_cutter_is_a_cutter_that_can_be_set_up() {
        // a deep cut: every suggested R1 must exceed the depth
        let setup = Setup {
            cutter_radius_mm: 50.0,
            stock_radius_mm: 10.0,
            depth_mm: 9.6,
            ratio: Ratio::new(2, 1).unwrap(),
            edges: 3,
            direction: Direction::Same,
        };
        for tol in [0.001, 0.01, 0.1, 1.0] {
            if let Some(r) = min_cutter(&setup, tol) {
                assert!(Setup { cutter_radius_mm: r, ..setup }.validate().is_ok(), "{tol}: R1 {r}");
            }
        }
    }

    #[test]
    fn min_cutter_radius_meets_the_tolerance_just_barely() {
        let setup = Setup {
            cutter_radius_mm: 50.0,
            stock_radius_mm: 10.0,
            depth_mm: 4.0,
            ratio: Ratio::new(1, 1).unwrap(),
            edges: 3,
            direction: Direction::Same,
        };
        let r = min_cutter(&setup, 0.05).expect("some cutter flattens a 1:1 triangle to 50 µm");
        let dev = |r1| Setup { cutter_radius_mm: r1, ..setup }.summary().unwrap().flat_deviation.abs();
        assert!(dev(r) <= 0.05 && dev(r * 0.97) > 0.05, "{r}");
    }
}
