//! Speed figures for the README (not enforced by tests):
//!   cargo bench -p polyturn-host --bench host
//! * geometry: one default `polyturn geometry` computation (goal < 100 ms)
//! * simulate: control ticks per second of the full simulation (goal ≥ 10 M/s)
//! * tick: the sync core's tick alone, on this PC
//! * planner: `polyturn setups` at the edge of its flags' ranges, the
//!   slowest requests found (goal < 1 s; 173 s before the sector solver)

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use polyturn_host::geometry::{Direction, Section, Setup};
use polyturn_host::planner::{plan, Request};
use polyturn_host::sim::{run, Scenario, Start};
use polyturn_sync::{Config, Controller, DriveKind, Ratio, TickInput, Timing};
use std::hint::black_box;

fn hexagon() -> Setup {
    Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 1.5,
        ratio: Ratio::TWO,
        edges: 3,
        direction: Direction::Same,
    }
}

fn geometry(c: &mut Criterion) {
    let s = hexagon();
    c.bench_function("geometry: default polyturn geometry (hexagon)", |b| {
        b.iter(|| black_box(Section::ideal(black_box(&s), Section::default_bins(6)).summary()))
    });
}

fn simulate(c: &mut Criterion) {
    let sc = Scenario::standard(hexagon(), 600.0, 10.0, 0.02, Start::Spinning, 2400, 3200, DriveKind::Stepper, 1);
    let ticks = run(&sc).expect("runs").ticks;
    let mut g = c.benchmark_group("simulate");
    g.throughput(Throughput::Elements(ticks));
    g.sample_size(10);
    g.bench_function("hexagon 600 rpm, 10 revolutions, with cutting (ticks)", |b| {
        b.iter(|| black_box(run(&sc).expect("runs")))
    });
    g.finish();
}

fn tick(c: &mut Criterion) {
    let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    let _ = ctl.engage();
    let (mut pos, mut emitted) = (0u32, 0u16);
    let mut g = c.benchmark_group("core");
    g.throughput(Throughput::Elements(1));
    g.bench_function("tick, synced at 600 rpm", |b| {
        b.iter(|| {
            pos += 246;
            let out = ctl.tick(&TickInput { lathe: (pos >> 8) as u16, emitted, ..TickInput::default() });
            emitted = emitted.wrapping_add(out.plan.count);
            black_box(out)
        })
    });
    g.finish();
}

/// `polyturn setups --sides 2 --stock-radius 10 --depth 1.5 --max-edges 12
/// --max-ratio 1000 --max-revolutions 12`: 144 candidates, the smallest
/// cutter searched for each (173 s before the sector solver); and the same
/// for 3 sides cut 9.6 mm deep, the slowest request found since.
fn planner(c: &mut Criterion) {
    let worst = Request {
        sides: 2,
        stock_radius: 10.0,
        depth: 1.5,
        cutter_radius: None,
        max_edges: 12,
        max_ratio: 1000.0,
        max_revolutions: 12,
        rpm: None,
        tolerance: 0.01,
    };
    let deep = Request { sides: 3, depth: 9.6, ..worst };
    let mut g = c.benchmark_group("planner");
    g.sample_size(10);
    g.bench_function("setups 2 sides, 12 edges, 12 turns, ratio <= 1000", |b| {
        b.iter(|| black_box(plan(black_box(&worst))))
    });
    g.bench_function("setups 3 sides 9.6 mm deep, 12 edges, 12 turns, ratio <= 1000", |b| {
        b.iter(|| black_box(plan(black_box(&deep))))
    });
    g.finish();
}

criterion_group!(benches, geometry, simulate, tick, planner);
criterion_main!(benches);
