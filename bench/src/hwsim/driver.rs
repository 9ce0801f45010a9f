//! What a stepper driver sees on STEP (PA8) and DIR (PA9): the pin edges
//! of the peripheral model, judged by a driver's timing rules.

use polyturn_stm32_model::{Edge, PinId};

/// The driver's view of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Received {
    /// net steps, each rising edge counted the way DIR pointed
    pub steps: i64,
    pub pulses: u64,
    /// pulses a driver needing `pulse` high and low could miss
    pub unseen: u64,
    pub min_high: u64,
    pub min_low: u64,
    /// shortest DIR-change to rising-edge time
    pub min_dir_setup: u64,
    /// DIR changes while STEP was high (never allowed)
    pub dir_while_high: u64,
    /// changes of DIR between pulses of opposite directions
    pub reversals: u64,
    /// rising edges, in cycles
    pub rises: Vec<u64>,
    /// rising edges that reversed the direction, in cycles
    pub reversed_at: Vec<u64>,
}

/// Reads `edges` in order; `pulse` is the high and low time the driver
/// needs, in cycles; `dir` the DIR level before the first edge.
pub fn receive(edges: &[Edge], pulse: u64, mut dir: bool) -> Received {
    let mut r = Received { min_high: u64::MAX, min_low: u64::MAX, min_dir_setup: u64::MAX, ..Received::default() };
    let (mut step, mut last_rise, mut last_fall, mut last_dir) = (false, None::<u64>, None::<u64>, None::<u64>);
    let mut last_step_dir = None::<bool>;
    for e in edges {
        match (e.pin, e.high) {
            (PinId::Pa8, true) if !step => {
                step = true;
                let low = last_fall.map_or(u64::MAX, |f| e.cycle - f);
                r.min_low = r.min_low.min(low);
                if let Some(d) = last_dir {
                    r.min_dir_setup = r.min_dir_setup.min(e.cycle - d);
                }
                if last_step_dir.is_some_and(|d| d != dir) {
                    r.reversals += 1;
                    r.reversed_at.push(e.cycle);
                }
                last_step_dir = Some(dir);
                last_dir = None;
                last_rise = Some(e.cycle);
                r.pulses += 1;
                r.steps += if dir { 1 } else { -1 };
                r.rises.push(e.cycle);
                if low < pulse {
                    r.unseen += 1;
                }
            }
            (PinId::Pa8, false) if step => {
                step = false;
                let high = e.cycle - last_rise.unwrap_or(e.cycle);
                r.min_high = r.min_high.min(high);
                if high < pulse {
                    r.unseen += 1;
                }
                last_fall = Some(e.cycle);
            }
            (PinId::Pa9, level) if level != dir => {
                dir = level;
                last_dir = Some(e.cycle);
                if step {
                    r.dir_while_high += 1;
                }
            }
            _ => {}
        }
    }
    r
}
