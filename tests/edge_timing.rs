//! Phase at the limit of what the encoder can tell: with A's
//! rises timed to the µs, the position between counts comes from the
//! edge's place and age, not the count's ±½. The limits are the physics:
//! 0.5 × (steps per count) + 0.5 step synchronised (the count's own
//! uncertainty plus the motor's step), 0.1 count + 0.5 step while cutting.
//! Each scenario runs with the edge times and without them (the count
//! alone), so the gain is shown to come from the edge times.

use polyturn_host::geometry::Direction;
use polyturn_host::sim::encoder::Disc;
use polyturn_host::sim::{Scenario, SimResult, Start};
use polyturn_scenarios::*;
use polyturn_sync::DriveKind;

/// One row of the table: a scenario, with its steps per count.
struct Row {
    sc: Scenario,
    steps_per_count: f64,
}

fn row(ratio: &str, edges: u32, dir: Direction, rpm: f64, ripple: f64, start: Start) -> Row {
    let setup = setup(ratio, edges, dir, 2.0);
    let steps_per_count = setup.ratio.to_f64() * 3200.0 / 2400.0;
    Row { sc: scenario(setup, rpm, 20.0, ripple, start, DriveKind::Stepper), steps_per_count }
}

fn rows() -> [Row; 4] {
    [
        row("2", 3, Direction::Same, 600.0, 0.02, Start::Rest),
        row("11/3", 3, Direction::Same, 300.0, 0.05, Start::Spinning),
        row("7/2", 2, Direction::Opposite, 400.0, 0.02, Start::Rest),
        row("4/3", 3, Direction::Same, 900.0, 0.02, Start::Spinning),
    ]
}

fn cutting_limit(r: &Row) -> f64 {
    0.1 * r.steps_per_count + 0.5
}

fn synced_limit(r: &Row) -> f64 {
    0.5 * r.steps_per_count + 0.5
}

fn run_with(r: &Row, edge_timing: bool, disc: Disc) -> SimResult {
    let mut sc = r.sc.clone();
    sc.edge_timing = edge_timing;
    sc.disc = disc;
    let out = simulate(&sc);
    assert!(out.faults.is_empty(), "{:?}", out.faults);
    assert_eq!(out.final_error_steps, 0, "drift");
    out
}

/// The row with the edge times, on `disc`: its phase error while cutting
/// within a tenth of a count and half a step.
fn cuts_within_its_limit(r: &Row, disc: Disc) -> SimResult {
    let with = run_with(r, true, disc);
    let limit = cutting_limit(r);
    let got = with.max_error_steps_cutting;
    assert!(got <= limit, "{}: {got} > {limit}", r.sc.setup.ratio);
    with
}

#[test]
fn with_edge_times_every_scenario_cuts_within_a_tenth_of_a_count() {
    for r in rows() {
        let with = cuts_within_its_limit(&r, Disc::default());
        let without = run_with(&r, false, Disc::default());
        // and the count alone does not: the gain is the edge times'
        assert!(
            without.max_error_steps_cutting > 1.5 * with.max_error_steps_cutting,
            "{}: {} without against {} with",
            r.sc.setup.ratio,
            without.max_error_steps_cutting,
            with.max_error_steps_cutting
        );
    }
}

/// Engaged while spinning, the whole synchronised run (run-down to rest
/// included) stays within the count's own ±½ plus a step. From rest it
/// does not: the first count comes half a count after the lathe moved,
/// and the motor's acceleration limit (400 000 steps/s²) then sets how
/// fast the cutter catches up; no estimate can be earlier than the first
/// count (docs/src/performance.md).
#[test]
fn engaged_while_spinning_the_synced_error_is_within_the_counts_own_half() {
    for r in rows().into_iter().filter(|r| r.sc.lathe.start_rpm > 0.0) {
        let with = run_with(&r, true, Disc::default());
        let limit = synced_limit(&r);
        assert!(with.max_error_steps <= limit, "{}: {} > {limit}", r.sc.setup.ratio, with.max_error_steps);
    }
}

/// With a start rate (`start-rate 3200`: one turn a second, 200 full
/// steps/s at 1/16, what nanoELS starts its steppers at), every scenario,
/// engaged at rest or spinning, with a true encoder or a cheap one, is
/// within the synchronised limit: the cutter takes the lathe's speed at
/// its first count instead of catching up at `max-accel`. Without it, from
/// rest, it is not (the bound in docs/src/performance.md).
#[test]
fn with_a_start_rate_every_scenario_is_within_its_synchronised_limit() {
    let cheap = Disc { quadrature_counts: 0.12, duty_counts: 0.04, ..Disc::default() };
    for mut r in rows() {
        let limit = synced_limit(&r);
        if r.sc.lathe.start_rpm == 0.0 {
            let without = run_with(&r, true, Disc::default()).max_error_steps;
            assert!(without > limit, "{}: {without} without a start rate", r.sc.setup.ratio);
        }
        r.sc.core.start_rate_hz = 3200;
        for disc in [Disc::default(), cheap] {
            let got = run_with(&r, true, disc).max_error_steps;
            assert!(got <= limit, "{} {disc:?}: {got} > {limit}", r.sc.setup.ratio);
        }
    }
}

/// A cheap 600-line encoder: B ±3 % of a cycle off 90° (0.12 count) and A's
/// duty 1 % off. Only A's rises are timed, and A rises at the same place
/// of every cycle, so neither error reaches the timing.
#[test]
fn a_cheap_encoders_quadrature_and_duty_errors_leave_the_cut_within_its_limit() {
    let disc = Disc { quadrature_counts: 0.12, duty_counts: 0.04, ..Disc::default() };
    for r in rows() {
        cuts_within_its_limit(&r, disc);
    }
}

/// An eccentric disc moves every edge, and the count with it: the lathe's
/// angle is wrong by the eccentricity, and no timing of the edges can
/// tell. The cutter follows the disc, so the phase error while cutting is
/// the eccentricity (in steps) plus what the timing leaves.
#[test]
fn a_discs_eccentricity_reaches_the_cut_as_itself_and_no_more() {
    let r = &rows()[0];
    let ecc = 0.38;
    let with = run_with(r, true, Disc { eccentricity_counts: ecc, ..Disc::default() });
    let bound = ecc * r.steps_per_count + cutting_limit(r);
    assert!(with.max_error_steps_cutting > 0.8 * ecc * r.steps_per_count, "{}", with.max_error_steps_cutting);
    assert!(with.max_error_steps_cutting <= bound, "{} > {bound}", with.max_error_steps_cutting);
}
