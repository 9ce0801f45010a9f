//! Speed figures for the README (not enforced by tests):
//!   cargo bench -p polyturn-host --bench host
//! * geometry: one default `polyturn geometry` computation (goal < 100 ms)
//! * simulate: control ticks per second of the full simulation (goal ≥ 10 M/s)
//! * tick: the sync core's tick alone, on this PC

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use polyturn_host::geometry::{Direction, Section, Setup};
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

criterion_group!(benches, geometry, simulate, tick);
criterion_main!(benches);
