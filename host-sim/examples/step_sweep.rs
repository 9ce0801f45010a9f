//! Issue 11's sweep of the step output on the peripheral model, as a table.
//! `cargo run --release -p polyturn-host --example step_sweep`
use polyturn_host::hwsim::scenarios::{lathe, ramp, rocking, steady, Outcome};
use polyturn_host::hwsim::Isr;
use polyturn_stm32_model::Params;
use polyturn_sync::Config;

fn row(name: &str, o: &Outcome) {
    let r = &o.received;
    let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1}"));
    println!(
        "{name:<34} {:>8} {:>8} {:>8} {:>5} {:>6} {:>6} {:>6} {:>8} {:>4}/{:<4}/{:<4} {:>4} {:>4} {}",
        r.steps,
        o.believed,
        o.exact,
        r.unseen,
        r.min_high,
        r.min_low,
        f(o.spacing_error),
        f(o.delay),
        r.reversals,
        o.command_reversals,
        o.target_reversals,
        o.late,
        o.overruns,
        o.faults.join(",")
    );
}

fn main() {
    println!(
        "{:<34} {:>8} {:>8} {:>8} {:>5} {:>6} {:>6} {:>6} {:>8} {:>11} {:>4} {:>4} faults",
        "scenario", "driver", "core", "exact", "unseen", "hi", "lo", "space", "delay", "rev/cmd/exact", "late", "ovr"
    );
    for lat in [(200, 400), (900, 1_100), (1_800, 2_000), (200, 2_000)] {
        let isr = Isr::new(lat);
        for hz in [1, 10, 100, 1_000, 10_000, 64_000, 150_000, 250_000] {
            let ticks = (25_000 * 3 / hz).clamp(500, 25_000 * 2);
            let o = steady(hz * 1000, ticks, isr, Params::default());
            row(&format!("steady {hz} Hz, isr {}-{}", lat.0, lat.1), &o);
        }
        let c = |ratio: &str, rpm: &str| {
            let base = Config::default().with("max-rate", "250000").unwrap().with("max-rpm", rpm).unwrap();
            base.with("ratio", ratio).unwrap()
        };
        let o = lathe(c("2", "2300"), &ramp(2400.0, 2300.0, 1.0, 0.3), 2.6, isr, Params::default(), None);
        row(&format!("ramp 2300 rpm 2:1, isr {}-{}", lat.0, lat.1), &o);
        let o = lathe(c("11/3", "1250"), &ramp(2400.0, 1250.0, 1.0, 0.3), 2.6, isr, Params::default(), None);
        row(&format!("ramp 1250 rpm 11/3, isr {}-{}", lat.0, lat.1), &o);
        let o = lathe(c("2", "2000"), &rocking(40.0, 1.0), 1.3, isr, Params::default(), None);
        row(&format!("rocked by hand, isr {}-{}", lat.0, lat.1), &o);
        let o = lathe(c("2", "2000"), &ramp(2400.0, 600.0, 0.3, 1.0), 1.9, isr, Params::default(), Some((0.6, 0.65)));
        row(&format!("estop at 600 rpm, re-engage, isr {}-{}", lat.0, lat.1), &o);
    }
}
