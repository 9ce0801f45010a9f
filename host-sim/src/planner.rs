//! The setup planner: every (ratio, edges, direction) that cuts N flats,
//! with what a machinist needs to choose between them.

use crate::geometry::{Direction, Refusal, Section, Setup, SetupError, LENGTH_MM};
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

/// The smallest cutter radius, from R2/2 (or just over the depth) up to
/// [`min_cutter_scan_top`], that `geometry` takes with flats within `tol`,
/// rounded up to 3 significant figures (a size to make, printed whole).
/// The one-sector estimate finds it in a fraction of the time where it
/// agrees with `geometry` (sharp corners); where `geometry` finds its
/// answer out of `tol`, or it finds none, `geometry`'s own figure is
/// searched.
fn min_cutter(setup: &Setup, tol: f64) -> Option<f64> {
    let estimate = estimated_min_cutter(setup, tol).map(round_up_3).filter(|&r| meets(setup, r, tol));
    estimate.or_else(|| searched_min_cutter(setup, tol))
}

/// The least radius whose one-sector estimate of the flats is within
/// `tol`: geometric steps, then bisection. Only a guess: `geometry` judges
/// the section over the whole circle at its own bins, and a round-cornered
/// section's flats may come out 0.9 mm apart.
fn estimated_min_cutter(setup: &Setup, tol: f64) -> Option<f64> {
    let dev = |r1: f64| {
        let s = Section::ideal_sector(&Setup { cutter_radius_mm: r1, ..*setup }, 128);
        s.flat_deviation(0).abs()
    };
    let top = min_cutter_scan_top(setup.stock_radius_mm);
    let mut r = scan_start(setup);
    let mut prev = r;
    while dev(r) > tol {
        if r >= top {
            return None;
        }
        prev = r;
        r = (r * 1.25).min(top);
    }
    Some(bisect(prev, r, 20, |mid| dev(mid) <= tol))
}

/// The first radius either scan tries: R2/2, but no smaller than the depth
/// (a cutter whose radius does not exceed it would have its axis inside
/// the bar, `Setup::validate`) nor than `geometry` takes.
fn scan_start(setup: &Setup) -> f64 {
    (setup.stock_radius_mm * 0.5).max(setup.depth_mm * 1.01).max(LENGTH_MM.0)
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

/// [`min_cutter`] on `geometry`'s figure:
/// geometric steps, then bisection between the last that fails and the
/// first that meets it, then rounded up. The deviation need not fall
/// monotonically with the radius: where it changes sign between two steps,
/// the radii between are searched for one within `tol`; and each answer
/// is checked as given, one that fails once rounded being given unrounded.
fn searched_min_cutter(setup: &Setup, tol: f64) -> Option<f64> {
    let top = min_cutter_scan_top(setup.stock_radius_mm);
    let mut r = scan_start(setup);
    let mut failed: Option<(f64, Option<f64>)> = None;
    loop {
        let dev = deviation(setup, r);
        if dev.is_some_and(|d| d.abs() <= tol) {
            break;
        }
        let sign_change = match (failed, dev) {
            (Some((lo, Some(d0))), Some(d1)) if (d0 > 0.0) != (d1 > 0.0) => crossing(setup, lo, d0, r, tol),
            _ => None,
        };
        if let Some(x) = sign_change {
            r = x;
            break;
        }
        if r >= top {
            return None;
        }
        failed = Some((r, dev));
        r = (r * 1.5).min(top);
    }
    if let Some((lo, _)) = failed {
        // 9 halvings of a 50 % step: 0.1 %, inside the rounding
        r = bisect(lo, r, 9, |mid| meets(setup, mid, tol));
    }
    let rounded = round_up_3(r);
    Some(if meets(setup, rounded, tol) { rounded } else { r })
}

/// A radius between `lo` (deviation `d_lo`, out of `tol`) and `hi` (out of
/// it on the other side) whose deviation is within `tol`, by bisection on
/// the sign; None if `geometry` refuses one on the way or none is found.
fn crossing(setup: &Setup, mut lo: f64, d_lo: f64, mut hi: f64, tol: f64) -> Option<f64> {
    // 16 halvings of a 50 % step: 8 ppm of the radius
    for _ in 0..16 {
        let mid = 0.5 * (lo + hi);
        let d = deviation(setup, mid)?;
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

/// `r` rounded up to 3 significant figures, as the nearest float to its
/// decimal (so it prints as those figures).
fn round_up_3(r: f64) -> f64 {
    let unit = 10f64.powi(r.log10().floor() as i32 - 2);
    let up = (r / unit).ceil() * unit;
    let decimals = (2 - r.log10().floor() as i32).max(0) as usize;
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
