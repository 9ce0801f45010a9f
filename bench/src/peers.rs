//! polyturn's core beside its peers' published gearbox algorithms on one
//! lathe trace, to show it ahead of every peer on the same trace: the
//! same lathe and 2 400-count encoder, the same rotor, the same
//! measurement. The peers are re-implemented from their sources (each
//! module cites the file and lines); what they leave open, and what this
//! comparison chooses for them, is written in each.
//!
//! Every controller is engaged with the lathe at rest and follows it up to
//! speed, through the cut and back to rest. The error is the exact gear's
//! position less the rotor's, in steps, less the controller's mean error
//! while cutting: a constant phase is set once on the machine (the peers
//! take the count for the position, ½ count from the edges this encoder
//! places its counts between, and truncate), so it is no fault of theirs.

pub mod clough42;
pub mod didge;
mod measure;
pub mod nanoels;
pub mod trace;

use polyturn_host::sim::lathe::{LatheProfile, Leg};
use polyturn_host::sim::Scenario;

/// The controllers, in `trace::Trace::steps`'s order.
pub const NAMES: [&str; 6] =
    ["polyturn", "Clough42 (f32)", "Clough42 (integer)", "nanoELS", "Didge*, no delay", "Didge*, delayed"];

/// The peers that run here as published (Didge runs generalised: it
/// refuses more than one step a count, `didge`).
pub fn as_published(name: &str) -> bool {
    name.starts_with("Clough42") || name == "nanoELS"
}

/// A scenario of the comparison: the simulator's settings, run from rest.
pub struct Case {
    pub sc: Scenario,
    pub rpm: f64,
    pub revolutions: f64,
}

impl Case {
    /// The lathe: up to `rpm` at the simulator's 1 200 rpm/s, `revolutions`
    /// there, down to rest and 0.3 s more.
    pub fn profile(&self) -> LatheProfile {
        let p = &self.sc.lathe;
        let legs = vec![
            Leg { rpm: self.rpm, accel_rpm_per_s: 1200.0, hold_s: 3600.0 },
            Leg { rpm: 0.0, accel_rpm_per_s: 1200.0, hold_s: 0.3 },
        ];
        LatheProfile { start_rpm: 0.0, legs, ripple: p.ripple, wander: p.wander, dips: vec![] }
    }
}

/// One controller's figures on the trace.
#[derive(Clone, Debug)]
pub struct Figures {
    pub name: &'static str,
    /// the worst error over the whole run (polyturn: while synchronised)
    pub synced: f64,
    /// the worst error while cutting
    pub cutting: f64,
    /// the constant phase taken out (its mean error while cutting)
    pub bias: f64,
    /// the largest change of a step interval to the next while cutting
    pub jerk: f64,
}

/// Runs `case` and measures every controller on it.
pub fn compare(case: &Case) -> Result<Vec<Figures>, String> {
    let tr = trace::run(case)?;
    if !tr.faults.is_empty() {
        return Err(format!("polyturn faulted: {:?}", tr.faults));
    }
    let core = &case.sc.core;
    let sense = if core.sense == polyturn_sync::Sense::Same { 1.0 } else { -1.0 };
    let spc = core.ratio.to_f64() * core.motor_steps_per_rev as f64 / core.encoder_counts_per_rev as f64;
    let (origin, turns) = tr.origin;
    let ideal: Vec<f64> = tr.instants.iter().map(|i| sense * spc * (i.u - origin as f64) + turns as f64).collect();
    let cut: Vec<f64> = tr.instants.iter().filter(|i| i.cutting).map(|i| i.t).collect();
    let window = (cut.first().copied().unwrap_or(0.0), cut.last().copied().unwrap_or(0.0));
    Ok(NAMES
        .iter()
        .zip(&tr.steps)
        .enumerate()
        .map(|(k, (name, steps))| {
            let rotor = measure::rotor(steps, &tr.instants);
            let err: Vec<f64> = ideal.iter().zip(&rotor).map(|(i, r)| i - r).collect();
            let cutting = |j: &usize| tr.instants[*j].cutting;
            let n = (0..err.len()).filter(cutting).count().max(1) as f64;
            let bias = (0..err.len()).filter(cutting).map(|j| err[j]).sum::<f64>() / n;
            let counted = |j: &usize| k != 0 || tr.instants[*j].synced;
            let worst = |f: &dyn Fn(&usize) -> bool| {
                (0..err.len()).filter(f).map(|j| (err[j] - bias).abs()).fold(0.0, f64::max)
            };
            Figures {
                name,
                synced: worst(&counted),
                cutting: worst(&cutting),
                bias,
                jerk: measure::interval_jerk(steps, window),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests;
