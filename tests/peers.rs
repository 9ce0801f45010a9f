//! polyturn beside its peers' gearbox algorithms on one lathe trace
//! (`polyturn_bench::peers`; docs/src/performance.md, "Beside the
//! peers"). While cutting, its phase error is at most half that of every
//! count-and-step peer (Clough42's and nanoELS as published, Didge's
//! Bresenham without its delay), with a true encoder and a cheap one, and
//! its steps stay evenly spaced where theirs jump; with the count alone it
//! is not. With a start rate its synchronised error, from rest included,
//! is no worse than any peer's. (Didge's delay generalised to every step,
//! on this model's exact edges, cuts closer still: the page says so.)

use polyturn_bench::peers::{as_published, compare, Case, Figures};
use polyturn_host::geometry::Direction;
use polyturn_host::sim::encoder::Disc;
use polyturn_host::sim::Start;
use polyturn_scenarios::*;
use polyturn_sync::DriveKind;

fn case(ratio: &str, edges: u32, dir: Direction, rpm: f64, ripple: f64) -> Case {
    let sc = scenario(setup(ratio, edges, dir, 2.0), rpm, 5.0, ripple, Start::Rest, DriveKind::Stepper);
    Case { sc, rpm, revolutions: 5.0 }
}

fn cases() -> [Case; 4] {
    [
        case("2", 3, Direction::Same, 600.0, 0.02),
        case("11/3", 3, Direction::Same, 300.0, 0.05),
        case("7/2", 2, Direction::Opposite, 400.0, 0.02),
        case("4/3", 3, Direction::Same, 900.0, 0.02),
    ]
}

/// The count-and-step peers: every one but Didge's generalised delay.
fn count_and_step(f: &[Figures]) -> impl Iterator<Item = &Figures> {
    f.iter().skip(1).filter(|x| as_published(x.name) || x.name == "Didge*, no delay")
}

fn best_cutting(f: &[Figures]) -> f64 {
    count_and_step(f).map(|x| x.cutting).fold(f64::INFINITY, f64::min)
}

#[test]
fn while_cutting_polyturn_is_within_half_every_count_and_step_peer_with_a_true_or_a_cheap_encoder() {
    for disc in [Disc::default(), Disc { quadrature_counts: 0.12, duty_counts: 0.04, ..Disc::default() }] {
        for mut c in cases() {
            c.sc.disc = disc;
            let f = compare(&c).expect("runs");
            let (poly, best) = (&f[0], best_cutting(&f));
            assert!(poly.cutting <= 0.5 * best, "{} {disc:?}: {} against {best}", c.sc.setup.ratio, poly.cutting);
            // evenly spaced: polyturn's intervals change by 1/256 of a
            // timer tick, theirs by whole ticks of their loops or bursts
            assert!(poly.jerk < 0.01, "{}: jerk {}", c.sc.setup.ratio, poly.jerk);
            for p in count_and_step(&f) {
                assert!(p.jerk > 0.5, "{}: {} jerk {}", c.sc.setup.ratio, p.name, p.jerk);
            }
        }
    }
}

/// The check above fails on a polyturn with the count alone: the gain
/// is the edge times'.
#[test]
fn with_the_count_alone_polyturn_is_not_within_half_while_cutting() {
    let behind = cases().into_iter().filter(|c| {
        let mut c = Case { sc: c.sc.clone(), ..*c };
        c.sc.edge_timing = false;
        let f = compare(&c).expect("runs");
        f[0].cutting > 0.5 * best_cutting(&f)
    });
    assert!(behind.count() >= 2);
}

/// From rest the peers start their motors at the lathe's speed at once;
/// with `start-rate 3200` polyturn's cutter does too, and its synchronised
/// error is then no worse than any peer's, Didge's delay included. Without
/// it, keeping to `max-accel`, it is worse than the best.
#[test]
fn with_a_start_rate_polyturn_is_synchronised_no_worse_than_any_peer() {
    for c in cases() {
        let f = compare(&c).expect("runs");
        let best = f.iter().skip(1).map(|x| x.synced).fold(f64::INFINITY, f64::min);
        assert!(f[0].synced > best, "{}: without a start rate {} against {best}", c.sc.setup.ratio, f[0].synced);
        let mut started = Case { sc: c.sc.clone(), ..c };
        started.sc.core.start_rate_hz = 3200;
        let ours = compare(&started).expect("runs")[0].synced;
        assert!(ours <= best, "{}: {ours} against {best}", c.sc.setup.ratio);
    }
}
