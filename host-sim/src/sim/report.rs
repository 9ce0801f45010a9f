//! `polyturn simulate` output: the JSON contract and the SVG (ideal vs
//! simulated section, and the phase error over time, magnified).

use super::{Scenario, SimResult};
use crate::geometry::svg::{outline, Drawing};
use serde_json::json;
use std::fmt::Write;

pub fn json(sc: &Scenario, r: &SimResult) -> serde_json::Value {
    let cut = crate::cli::geometry::report(&sc.setup, &r.section);
    let faults: Vec<_> =
        r.faults.iter().map(|(t, f)| json!({"tick": t, "kind": f.name(), "reason": f.reason()})).collect();
    json!({
        "final_error_steps": r.final_error_steps,
        "max_error_steps": r.max_error_steps,
        "max_error_deg": r.max_error_deg,
        "max_error_steps_cutting": r.max_error_steps_cutting,
        "max_profile_deviation": r.max_profile_deviation,
        "cut": cut,
        "ideal": crate::cli::geometry::report(&sc.setup, &r.ideal),
        "faults": faults,
        "ticks": r.ticks,
        "steps_emitted": r.steps_emitted,
        "encoder_counts": r.encoder_counts,
        "synced_ticks": r.synced_ticks,
        "tick_hz": sc.tick_hz,
        "motor_stalled": r.stalled,
        "max_shaft_error_steps": r.max_shaft_error_steps,
        "cut_turns": r.cut_turns,
    })
}

/// A few lines for a machinist.
pub fn human(sc: &Scenario, r: &SimResult) -> String {
    let s = r.section.summary();
    let calipers = crate::cli::measure::calipers(&s);
    let faults = if r.faults.is_empty() {
        "none".to_string()
    } else {
        r.faults.iter().map(|(t, f)| format!("{} at tick {t}", f.name())).collect::<Vec<_>>().join(", ")
    };
    format!(
        "setup: ratio {} x {} edges, {} sense, R1 {} R2 {} (stock diameter {}) DOC {} mm\n\
         cut: {} sides, {calipers}, flat deviation {:+.4} mm\n\
         worst phase error while synced: {:.2} steps ({:.4} deg of the work), while cutting: {:.2} steps\n\
         worst section deviation from the ideal: {:.2} µm\n\
         final error at rest: {} steps; faults: {faults}; {} ticks, {} steps",
        sc.setup.ratio,
        sc.setup.edges,
        sc.setup.direction.name(),
        sc.setup.cutter_radius_mm,
        sc.setup.stock_radius_mm,
        2.0 * sc.setup.stock_radius_mm,
        sc.setup.depth_mm,
        s.sides,
        s.flat_deviation,
        r.max_error_steps,
        r.max_error_deg,
        r.max_error_steps_cutting,
        r.max_profile_deviation * 1000.0,
        r.final_error_steps,
        r.ticks,
        r.steps_emitted,
    )
}

pub fn svg(sc: &Scenario, r: &SimResult) -> String {
    let r2 = sc.setup.stock_radius_mm;
    let size = 560.0;
    let mut d = Drawing::new(r2 * 1.4, size);
    d.circle(r2, r##"fill="none" stroke="#c33" stroke-width="1.5""##);
    d.path(&outline(&r.ideal.envelope), true, r##"fill="#3563" stroke="#124" stroke-width="1""##);
    // The simulated section with its deviation from the ideal magnified.
    let gain = magnification(r.max_profile_deviation, r2);
    let env = &r.section.envelope;
    let pts: Vec<(f64, f64)> = (0..env.bins())
        .step_by((env.bins() / 2048).max(1))
        .map(|i| {
            let t = env.angle(i);
            let ideal = r.ideal.envelope.radius[i];
            let rr = ideal + (env.radius[i] - ideal) * gain;
            (rr * t.cos(), rr * t.sin())
        })
        .collect();
    d.path(&pts, true, r##"fill="none" stroke="#e80" stroke-width="1.2""##);
    // The magnification said in words: "deviation x131" read as a
    // setting or a part number to the machinists who tried the page.
    d.text(0, "ideal section (blue), simulated section (orange)");
    if gain > 1.0 {
        d.text(1, &format!("orange's distance from blue drawn {gain:.0} times larger"));
    }
    d.text(
        2,
        &format!(
            "worst deviation {:.2} µm, worst phase error {:.2} steps",
            r.max_profile_deviation * 1000.0,
            r.max_error_steps
        ),
    );
    d.raw(&error_plot(r, size));
    d.finish(size + 200.0)
}

fn magnification(dev: f64, r2: f64) -> f64 {
    if dev <= 0.0 {
        return 1.0;
    }
    (r2 * 0.02 / dev).clamp(1.0, 1000.0).round()
}

/// Phase error (steps) against time, below the section.
fn error_plot(r: &SimResult, width: f64) -> String {
    let (top, h) = (width + 20.0, 160.0);
    let mut s = String::new();
    let _ =
        writeln!(s, r##"<rect x="40" y="{top}" width="{}" height="{h}" fill="none" stroke="#999"/>"##, width - 60.0);
    let lim = r.error_trace.iter().map(|b| b.1.abs().max(b.2.abs())).fold(0.5, f64::max);
    let t_end = r.error_trace.last().map(|b| b.0).unwrap_or(1.0).max(1e-6);
    let (x, y) = (|t: f64| 40.0 + t / t_end * (width - 60.0), |e: f64| top + h / 2.0 - e / lim * h / 2.0);
    for b in &r.error_trace {
        let _ = writeln!(
            s,
            r##"<line x1="{0:.1}" x2="{0:.1}" y1="{1:.1}" y2="{2:.1}" stroke="#c60"/>"##,
            x(b.0),
            y(b.1),
            y(b.2)
        );
    }
    let _ = writeln!(
        s,
        r##"<text x="44" y="{}" font-family="monospace" font-size="12">phase error while synced, +/-{lim:.2} steps full scale, 0..{t_end:.1} s</text>"##,
        top + 14.0
    );
    // the axes' scales and units at their ends
    let label = r##"font-family="monospace" font-size="11""##;
    let (left, bottom) = (38.0, top + h + 14.0);
    let _ = writeln!(s, r##"<text x="{left}" y="{:.1}" text-anchor="end" {label}>+{lim:.2}</text>"##, top + 10.0);
    let _ = writeln!(s, r##"<text x="{left}" y="{:.1}" text-anchor="end" {label}>0</text>"##, top + h / 2.0 + 4.0);
    let _ = writeln!(s, r##"<text x="{left}" y="{:.1}" text-anchor="end" {label}>-{lim:.2}</text>"##, top + h);
    let _ = writeln!(s, r##"<text x="40" y="{bottom:.1}" {label}>0 s</text>"##);
    let _ =
        writeln!(s, r##"<text x="{:.1}" y="{bottom:.1}" text-anchor="end" {label}>{t_end:.1} s</text>"##, width - 20.0);
    let _ = writeln!(
        s,
        r##"<text x="{:.1}" y="{bottom:.1}" text-anchor="middle" {label}>time; vertical: phase error, steps</text>"##,
        width / 2.0
    );
    s
}
