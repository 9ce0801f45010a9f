//! The sweep of the step output on the peripheral model, as a
//! Markdown table: `cargo run --release -p polyturn-bench --example step_sweep`
//! (`-- --all` for four interrupt-latency ranges instead of one).
use polyturn_bench::hwsim::scenarios::{lathe, ramp, rocking, steady, Outcome, TIMING};
use polyturn_bench::hwsim::steady_lathe::steady_lathe;
use polyturn_bench::hwsim::Isr;
use polyturn_stm32_model::Params;
use polyturn_sync::Config;

fn row(name: &str, o: &Outcome) {
    let r = &o.received;
    let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1}"));
    let low = if r.min_low > 10_000_000 { "-".to_string() } else { r.min_low.to_string() };
    let setup = if r.reversals == 0 { "-".to_string() } else { r.min_dir_setup.to_string() };
    let rev = format!("{}/{}/{}", r.reversals, o.command_reversals, o.target_reversals);
    let faults = if o.faults.is_empty() { "-".to_string() } else { o.faults.join(",") };
    let (spacing, delay, late) = (f(o.spacing_error), f(o.delay), o.late + o.overruns);
    println!(
        "| {name} | {} | {} | {} | {} | {} | {low} | {setup} | {spacing} | {delay} | {rev} | {late} | {faults} |",
        r.steps, o.believed, o.exact, r.unseen, r.min_high
    );
}

fn config(ratio: &str, rpm: &str) -> Config {
    let base = Config::default().with("max-rate", "250000").unwrap().with("max-rpm", rpm).unwrap();
    base.with("ratio", ratio).unwrap()
}

fn main() {
    let all = std::env::args().any(|a| a == "--all");
    let ranges: &[(u32, u32)] =
        if all { &[(200, 400), (900, 1_100), (1_800, 2_000), (200, 2_000)] } else { &[(200, 2_000)] };
    println!("Timer cycles at 96 MHz: pulse 2 us = 192, DIR setup 5 us = 480.\n");
    println!("| scenario | driver steps | core believes | exact target | unseen pulses | min high | min low | min DIR setup | spacing error | delay | reversals driver/commanded/exact | late+overrun | faults |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &lat in ranges {
        let isr = Isr::new(lat);
        let p = Params::default();
        let at = format!("ISR {}-{} cycles", lat.0, lat.1);
        for hz in [1, 10, 100, 1_000, 7_777, 10_000, 64_000, 123_457, 150_000, 250_000] {
            // three steps' time, within 20 ms and 2 s
            let tick_hz = u64::from(TIMING.tick_hz);
            let ticks = (tick_hz * 3 / hz).clamp(tick_hz / 50, tick_hz * 2);
            row(&format!("steady {hz} steps/s, {at}"), &steady(hz * 1000, ticks, isr, p));
        }
        let o = lathe(config("2", "2300"), &ramp(2400.0, 2300.0, 1.0, 0.3), 2.6, isr, p, None);
        row(&format!("0-2300-0 rpm at 2:1, {at}"), &o);
        let o = lathe(config("11/3", "1250"), &ramp(2400.0, 1250.0, 1.0, 0.3), 2.6, isr, p, None);
        row(&format!("0-1250-0 rpm at 11/3, {at}"), &o);
        let o = lathe(config("2", "2000"), &rocking(40.0, 1.0), 1.3, isr, p, None);
        row(&format!("rocked by hand +-40 counts 3 Hz, 37 Hz jitter, {at}"), &o);
        let o = lathe(config("2", "2000"), &ramp(2400.0, 600.0, 0.3, 1.0), 3.0, isr, p, Some((0.6, 0.65)));
        row(&format!("E-stop at 600 rpm, clear, engage again, {at}"), &o);
    }
    println!("\nA steady lathe through the whole controller, its encoder's edges latched as the board latches them (ISR 200-2000 cycles):\n");
    println!("| steps/s | steps judged | worst spacing, % of the period | driver reversals | faults |");
    println!("|---|---|---|---|---|");
    for hz in [1_000.0, 10_000.0, 64_000.0, 123_457.0, 240_000.0] {
        let (o, s) = steady_lathe(hz, Isr::new((200, 2_000)), Params::default());
        let faults = if o.faults.is_empty() { "-".to_string() } else { o.faults.join(",") };
        println!("| {hz} | {} | {:.2} | {} | {faults} |", s.steps, 100.0 * s.worst_fraction, o.received.reversals);
    }
}
