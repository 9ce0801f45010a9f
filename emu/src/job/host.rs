//! The same job in the host simulator (`polyturn_host::sim::run`): the same lathe
//! profile and seed, the same settings and `Timing`, engaged at the same moment
//! of the lathe's run. Both must end on the exact gear; the totals are compared.

use super::{scenario, Spec};
use polyturn_host::sim::{run, Event, Start};

/// Where the key's press is debounced: ENGAGE counts after it has held its level
/// for `keys::DEBOUNCE_MS`, read every millisecond.
const DEBOUNCE_S: f64 = (polyturn_firmware::keys::DEBOUNCE_MS + 1) as f64 / 1000.0;

pub struct HostRun {
    pub final_error_steps: i64,
    pub steps_emitted: u64,
    pub encoder_counts: i64,
    pub faults: usize,
}

pub fn simulate(spec: &Spec) -> Result<HostRun, String> {
    let mut sc = scenario(spec);
    // the emulated lathe runs its profile whole; the host's ends its hold when
    // the cut is done unless told not to
    sc.cut_revolutions = None;
    let engage_s = if spec.start == Start::Rest { 0.0 } else { spec.engage_after_ms as f64 / 1000.0 + DEBOUNCE_S };
    sc.events = vec![Event::Engage(engage_s)];
    let r = run(&sc).map_err(|e| format!("host simulation of {}: {e}", spec.name))?;
    Ok(HostRun {
        final_error_steps: r.final_error_steps,
        steps_emitted: r.steps_emitted,
        encoder_counts: r.encoder_counts,
        faults: r.faults.len(),
    })
}
