//! The planner's figures against the direct method's: `Section::ideal` on
//! a 0.5 µm polyline per evaluation, with no sector solver and no
//! per-ratio cache (173 s for `--sides 2 --max-edges 12 --max-ratio 1000
//! --max-revolutions 12`), whose rows for smaller requests of the same
//! shape are captured below (from the build of commit e7b03fd).
//!
//! The same rows, and the figures of each the polyline's on `geometry`'s
//! bins to within its own interpolation (1e-7 mm); each smallest cutter
//! one `geometry` takes with flats within the tolerance.

use super::{default_cutter, plan, Request};
use crate::geometry::{Direction, Roundness, Section, Setup};
use polyturn_sync::Ratio;

/// ratio, edges, direction, turns, flat deviation, sharp, min cutter radius
type Row = (&'static str, u32, &'static str, u32, f64, bool, Option<f64>);

fn req(sides: u32, stock_radius: f64, depth: f64, max_edges: u32, max_ratio: f64, max_revolutions: u32) -> Request {
    Request {
        sides,
        stock_radius,
        depth,
        cutter_radius: None,
        max_edges,
        max_ratio,
        max_revolutions,
        rpm: None,
        tolerance: 0.01,
    }
}

/// The row's setup with the request's cutter (the default's when none).
fn setup_of(req: &Request, ratio: &str, edges: u32, direction: &str) -> Setup {
    Setup {
        cutter_radius_mm: req.cutter_radius.unwrap_or_else(|| default_cutter(req.stock_radius)),
        stock_radius_mm: req.stock_radius,
        depth_mm: req.depth,
        ratio: Ratio::parse(ratio).unwrap(),
        edges,
        direction: if direction == "same" { Direction::Same } else { Direction::Opposite },
    }
}

/// The direct method's rows (captured before the planner left nearly round
/// sections out) less those `geometry` refuses, judged on the whole section.
fn polygons(req: &Request, direct: &[Row]) -> Vec<Row> {
    let round = |r: &Row| Roundness::of_setup(&setup_of(req, r.0, r.1, r.2)).0.is_round();
    direct.iter().filter(|r| !round(r)).copied().collect()
}

fn check(req: &Request, direct: &[Row]) {
    let outcome = plan(req);
    let (planned, direct) = (outcome.found, polygons(req, direct));
    // the same rows; their order follows `geometry`'s deviations
    let mut rows: Vec<_> = planned.iter().map(|c| (c.ratio.clone(), c.edges, c.direction, c.revolutions)).collect();
    let mut want: Vec<_> = direct.iter().map(|r| (r.0.to_string(), r.1, r.2, r.3)).collect();
    rows.sort();
    want.sort();
    assert_eq!(rows, want, "{} sides", req.sides);
    for c in &planned {
        let row = format!("{} sides: {} x {} {}", req.sides, c.ratio, c.edges, c.direction);
        let setup = setup_of(req, &c.ratio, c.edges, c.direction);
        let sampled = Section::ideal(&setup, Section::default_bins(setup.sides())).summary();
        assert!((c.flat_deviation - sampled.flat_deviation).abs() <= 1e-7, "{row}: {c:?} vs {sampled:?}");
        assert_eq!(c.corners_sharp, sampled.corners_sharp, "{row}");
        if let Some(r) = c.min_cutter_radius {
            assert!(within(&setup, r, req.tolerance), "{row}: {r}");
        }
    }
}

/// Whether `geometry` takes `setup` with cutter radius `r1`, with flats within `tol`.
fn within(setup: &Setup, r1: f64, tol: f64) -> bool {
    Setup { cutter_radius_mm: r1, ..*setup }.summary().is_ok_and(|s| s.flat_deviation.abs() <= tol)
}

#[test]
fn the_worst_requests_shape_plans_as_the_direct_method_on_smaller_requests() {
    check(&req(2, 10.0, 1.5, 3, 1000.0, 3), TWO_SIDES);
    check(&Request { rpm: Some(300.0), ..req(3, 10.0, 1.5, 3, 1000.0, 4) }, THREE_SIDES);
    check(&Request { rpm: Some(1000.0), ..req(1000, 10.0, 1.5, 4, 1000.0, 3) }, THOUSAND_SIDES);
    check(&Request { tolerance: 0.001, ..req(5, 1.0, 0.2, 4, 20.0, 2) }, FIVE_SIDES_SMALL);
}

/// The worst request itself (173 s by the direct method): its rows, shared
/// figures and order, and some rows' figures recomputed the direct way, on
/// the 0.5 µm polyline over the whole circle (every flat, not flat 0 alone).
#[test]
fn the_worst_request_agrees_with_the_sampled_section() {
    let req = req(2, 10.0, 1.5, 12, 1000.0, 12);
    let outcome = plan(&req);
    let rows = outcome.found;
    assert_eq!(rows.len() + outcome.round, 12 * 6 * 2, "every edge count, the odd turn counts, both senses");
    let bin = |d: f64| (d.abs() * 1e4).round();
    assert!(rows.windows(2).all(|w| bin(w[0].flat_deviation) <= bin(w[1].flat_deviation)));
    for a in &rows {
        for b in rows.iter().filter(|b| b.ratio == a.ratio && b.direction == a.direction) {
            assert_eq!(
                (a.flat_deviation, a.corners_sharp, a.min_cutter_radius),
                (b.flat_deviation, b.corners_sharp, b.min_cutter_radius)
            );
        }
    }
    let with_cutter: Vec<_> = rows.iter().filter(|c| c.min_cutter_radius.is_some()).collect();
    assert!(!with_cutter.is_empty());
    for c in
        [&rows[0], &rows[rows.len() / 2], &rows[rows.len() - 1], with_cutter[0], with_cutter[with_cutter.len() - 1]]
    {
        let setup = Setup {
            cutter_radius_mm: default_cutter(10.0),
            stock_radius_mm: 10.0,
            depth_mm: 1.5,
            ratio: Ratio::parse(&c.ratio).unwrap(),
            edges: c.edges,
            direction: if c.direction == "same" { Direction::Same } else { Direction::Opposite },
        };
        let sampled = Section::ideal(&setup, Section::default_bins(2)).summary();
        assert!((c.flat_deviation - sampled.flat_deviation).abs() <= 1e-7, "{c:?}: {}", sampled.flat_deviation);
        assert_eq!(c.corners_sharp, sampled.corners_sharp, "{c:?}");
        if let Some(r) = c.min_cutter_radius {
            // within, and (rounded up to 3 figures) not 3 % over the least
            let fails = |r1| {
                Setup { cutter_radius_mm: r1, ..setup }
                    .summary()
                    .map_or(true, |s| s.flat_deviation.abs() > req.tolerance)
            };
            assert!(within(&setup, r, req.tolerance) && (r == 5.0 || fails(r * 0.97)), "{c:?}");
        }
    }
}

/// `polyturn setups --sides 2 --stock-radius 10 --depth 1.5 --max-edges 3 --max-ratio 1000 --max-revolutions 3`
const TWO_SIDES: &[Row] = &[
    ("2", 1, "same", 1, 0.009886143081528687, false, Some(48.21866239623773)),
    ("1", 2, "same", 1, 0.27293787587355034, false, None),
    ("2", 1, "opposite", 1, -0.4501417453246957, false, Some(5.0)),
    ("2/9", 3, "opposite", 3, -0.45582271787535594, false, Some(39.386325312307235)),
    ("2/3", 3, "same", 1, 0.5567271793020354, false, None),
    ("2/3", 1, "same", 3, 0.5567271793020354, false, None),
    ("1", 2, "opposite", 1, -0.6447997817990593, false, Some(8.907429873943329)),
    ("2/3", 3, "opposite", 1, -0.8137199182822367, false, Some(13.249833136796951)),
    ("2/3", 1, "opposite", 3, -0.8137199182822367, false, Some(13.249833136796951)),
    ("1/3", 2, "opposite", 3, -1.1216178218764856, false, Some(26.310925704819965)),
    ("1/3", 2, "same", 3, 1.5236404438629716, false, None),
    ("2/9", 3, "same", 3, 2.6450256157710483, false, None),
];

/// `polyturn setups --sides 3 --stock-radius 10 --depth 1.5 --max-edges 3 --max-ratio 1000 --max-revolutions 4 --rpm 300`
const THREE_SIDES: &[Row] = &[
    ("3", 1, "same", 1, -0.07442505057066917, false, Some(425.0465923242508)),
    ("3/2", 2, "same", 1, 0.09690052315018159, false, Some(464.4746318504431)),
    ("3/2", 1, "same", 2, 0.09690052315018159, false, Some(464.4746318504431)),
    ("1", 3, "same", 1, 0.2774643570570028, false, None),
    ("3", 1, "opposite", 1, -0.38840143089498547, false, None),
    ("3/4", 2, "same", 2, 0.4528130003358264, false, None),
    ("3/4", 1, "same", 4, 0.4528130003358264, false, None),
    ("3/2", 2, "opposite", 1, -0.5305426546109144, false, None),
    ("3/2", 1, "opposite", 2, -0.5305426546109144, false, None),
    ("1", 3, "opposite", 1, -0.6624040120534902, false, Some(9.250130504369736)),
    ("3/4", 2, "opposite", 2, -0.783636703185401, false, None),
    ("3/4", 1, "opposite", 4, -0.783636703185401, false, None),
    ("1/2", 3, "same", 2, 0.8486033392501015, false, None),
    ("1/2", 3, "opposite", 2, -0.9922535511839286, false, Some(18.194823496742174)),
    ("1/4", 3, "opposite", 4, -1.0834554526199858, false, Some(36.11330612329766)),
    ("3/8", 2, "opposite", 4, -1.149483768166414, false, None),
    ("3/8", 2, "same", 4, 1.2786596879575076, false, None),
    ("1/4", 3, "same", 4, 2.232712855845229, false, None),
];

/// `polyturn setups --sides 1000 --stock-radius 10 --depth 1.5 --max-edges 4 --max-ratio 1000 --max-revolutions 3 --rpm 1000`
const THOUSAND_SIDES: &[Row] = &[
    ("250/3", 4, "same", 3, -6.930976352848007e-06, true, Some(5.0)),
    ("250/3", 4, "opposite", 3, -7.334120498470043e-06, true, Some(5.0)),
    ("1000/9", 3, "same", 3, -6.980767338404804e-06, true, Some(5.0)),
    ("1000/9", 3, "opposite", 3, -7.285491772535124e-06, true, Some(5.0)),
    ("500/3", 2, "same", 3, -7.035029264912397e-06, true, Some(5.0)),
    ("500/3", 2, "opposite", 3, -7.233273969120547e-06, true, Some(5.0)),
    ("250", 4, "same", 1, -7.063896349635002e-06, true, Some(5.0)),
    ("250", 4, "opposite", 1, -7.200074605862029e-06, true, Some(5.0)),
    ("1000/3", 3, "same", 1, -7.084976925142428e-06, true, Some(5.0)),
    ("1000/3", 3, "opposite", 1, -7.18270145050326e-06, true, Some(5.0)),
    ("1000/3", 1, "same", 3, -7.084976925142428e-06, true, Some(5.0)),
    ("1000/3", 1, "opposite", 3, -7.18270145050326e-06, true, Some(5.0)),
    ("500", 2, "same", 1, -7.101637516271354e-06, true, Some(5.0)),
    ("500", 2, "opposite", 1, -7.168090983000752e-06, true, Some(5.0)),
    ("1000", 1, "same", 1, -7.113890651666566e-06, true, Some(5.0)),
    ("1000", 1, "opposite", 1, -7.1518055122510304e-06, true, Some(5.0)),
];

/// `polyturn setups --sides 5 --stock-radius 1 --depth 0.2 --max-edges 4 --max-ratio 20 --max-revolutions 2 --tolerance 0.001`
const FIVE_SIDES_SMALL: &[Row] = &[
    ("5/2", 2, "same", 1, -0.005275972231826631, true, Some(0.6216665506362915)),
    ("5/2", 1, "same", 2, -0.005275972231826631, true, Some(0.6216665506362915)),
    ("5/3", 3, "same", 1, 0.007120765380370986, true, Some(34.15307649989774)),
    ("5/4", 4, "same", 1, 0.017848725563718082, true, Some(100.66872873094876)),
    ("5/4", 2, "same", 2, 0.017848725563718082, true, Some(100.66872873094876)),
    ("5", 1, "same", 1, -0.018147020596544938, false, Some(101.23129636580933)),
    ("5/6", 3, "same", 2, 0.0355330639980852, true, None),
    ("5", 1, "opposite", 1, -0.04258387404852254, false, None),
    ("5/8", 4, "same", 2, 0.049540914107630285, true, None),
    ("5/2", 2, "opposite", 1, -0.05489526544821727, false, None),
    ("5/2", 1, "opposite", 2, -0.05489526544821727, false, None),
    ("5/3", 3, "opposite", 1, -0.06539257785760899, false, None),
    ("5/4", 4, "opposite", 1, -0.07507627871124889, false, None),
    ("5/4", 2, "opposite", 2, -0.07507627871124889, false, None),
    ("5/6", 3, "opposite", 2, -0.09487752577697951, false, None),
    ("5/8", 4, "opposite", 2, -0.11283362063170436, false, None),
];
