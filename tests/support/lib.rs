//! Shared builders for the workspace scenario tests (tests/*.rs).

use polyturn_host::geometry::{Direction, Setup};
use polyturn_host::sim::{run, Scenario, SimResult, Start};
use polyturn_sync::{DriveKind, Ratio};

/// The control tick's rate, the board's (`polyturn_sync::Timing::FIRMWARE`).
pub const TICK_HZ: u32 = polyturn_sync::Timing::FIRMWARE.tick_hz;

/// Seconds from the start to tick `tick`.
pub fn seconds(tick: u64) -> f64 {
    tick as f64 / TICK_HZ as f64
}

/// R1 = 50, R2 = 10 mm, the reference cutter and stock.
pub fn setup(ratio: &str, edges: u32, direction: Direction, depth: f64) -> Setup {
    Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: depth,
        ratio: Ratio::parse(ratio).expect("valid ratio"),
        edges,
        direction,
    }
}

pub fn hexagon() -> Setup {
    setup("2", 3, Direction::Same, 1.5)
}

/// Defaults of `polyturn simulate`: 2400-count encoder, 3200-step motor.
pub fn scenario(setup: Setup, rpm: f64, revs: f64, ripple: f64, start: Start, drive: DriveKind) -> Scenario {
    Scenario::standard(setup, rpm, revs, ripple, start, 2400, 3200, drive, 7)
}

pub fn simulate(sc: &Scenario) -> SimResult {
    run(sc).expect("scenario runs")
}

/// Largest radial difference between two sections sampled alike.
pub fn section_gap(a: &polyturn_host::geometry::Section, b: &polyturn_host::geometry::Section) -> f64 {
    a.envelope.radius.iter().zip(&b.envelope.radius).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// A scripted run: the lathe runs through `legs` (rpm, hold seconds) at
/// `accel` rpm/s, then stops; cutting is not tied to a revolution count.
pub fn scripted(setup: Setup, start: Start, accel: f64, legs: &[(f64, f64)]) -> Scenario {
    use polyturn_host::sim::lathe::Leg;
    let mut sc = scenario(setup, legs.first().map_or(0.0, |l| l.0), 0.0, 0.0, start, DriveKind::Stepper);
    sc.cut_revolutions = None;
    sc.lathe.legs = legs.iter().map(|&(rpm, hold_s)| Leg { rpm, accel_rpm_per_s: accel, hold_s }).collect();
    sc
}
