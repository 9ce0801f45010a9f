//! polyturn beside its peers' gearbox algorithms on one lathe trace per
//! scenario (`polyturn_bench::peers`):
//!   cargo run --release -p polyturn-bench --example peers [cheap]
//! Phase error in steps (each controller's constant phase taken out),
//! and the largest change of one step interval to the next while cutting;
//! polyturn as set by default and with `start-rate 3200`.

use polyturn_bench::peers::{compare, Case, Figures};
use polyturn_host::geometry::{Direction, Setup};
use polyturn_host::sim::encoder::Disc;
use polyturn_host::sim::{Scenario, Start};
use polyturn_sync::{DriveKind, Ratio};

fn case(ratio: &str, edges: u32, direction: Direction, rpm: f64, ripple: f64) -> Case {
    let setup = Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 2.0,
        ratio: Ratio::parse(ratio).expect("ratio"),
        edges,
        direction,
    };
    let sc = Scenario::standard(setup, rpm, 20.0, ripple, Start::Rest, 2400, 3200, DriveKind::Stepper, 7);
    Case { sc, rpm, revolutions: 20.0 }
}

fn main() {
    // `cheap`: a cheap encoder's A/B skew (±3 % quadrature, 1 % duty error)
    let cheap = std::env::args().any(|a| a == "cheap");
    let mut cases = [
        ("2:1 × 3, 600 rpm, 2 %", case("2", 3, Direction::Same, 600.0, 0.02)),
        ("11/3 × 3, 300 rpm, 5 %", case("11/3", 3, Direction::Same, 300.0, 0.05)),
        ("7/2 × 2 opposite, 400 rpm, 2 %", case("7/2", 2, Direction::Opposite, 400.0, 0.02)),
        ("4/3 × 3, 900 rpm, 2 %", case("4/3", 3, Direction::Same, 900.0, 0.02)),
    ];
    for (_, c) in cases.iter_mut() {
        if cheap {
            c.sc.disc = Disc { quadrature_counts: 0.12, duty_counts: 0.04, ..Disc::default() };
        }
    }
    for (title, c) in &cases {
        println!("{title}");
        println!("  {:<22} {:>8} {:>8} {:>8} {:>10}", "controller", "synced", "cutting", "bias", "jerk");
        // and polyturn again with a start rate: one turn a second
        let mut started = Case { sc: c.sc.clone(), ..*c };
        started.sc.core.start_rate_hz = 3200;
        let mut rows = compare(c).expect("runs");
        rows.insert(1, Figures { name: "  start-rate 3200", ..compare(&started).expect("runs").remove(0) });
        for f in rows {
            println!("  {:<22} {:>8.2} {:>8.2} {:>8.2} {:>10.4}", f.name, f.synced, f.cutting, f.bias, f.jerk);
        }
    }
}
