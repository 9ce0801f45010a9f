//! The image's step stream against the host's sync core, tick by tick. The
//! host's `Controller` is fed the very inputs the image's tick read (`tape`),
//! given each command between the same two ticks as the image's (the entry of
//! `engage`, `disengage` and the index's `rebase`, hooked), and each of its plans is laid on the step timer's windows (`StepPlan::at`, two
//! ticks on: `steps::pipe`). Every rising edge at the driver must then come at
//! the host's planned cycle plus one fixed delay, the way the host planned it,
//! and ENABLE must agree at every tick: the ARM build of the core, the tick's
//! glue and the step ring make exactly the host core's stream.
//!
//! Why the inputs and not the host simulation's lathe: the host simulation
//! samples the lathe at the tick's instant, the image reads TIM3 at its
//! interrupt's latency, so a count arriving between the two is read one tick
//! apart. That is the sampling the edge-timed position is about
//! (`docs/src/emulator.md`), not a difference of the two builds.

use crate::chip::tape::{Command, Tape};
use polyturn_stm32_model::{Edge, PinId};
use polyturn_sync::steps::Dir;
use polyturn_sync::{Config, Controller, Timing};

/// What the comparison found.
pub struct Replay {
    /// ticks compared, and those whose ENABLE differed
    pub ticks: usize,
    pub enable_differs: usize,
    /// the host's planned steps and the rises at the driver (before `until`)
    pub planned: usize,
    pub rises: usize,
    /// the first rise whose time or direction differs: (index, what)
    pub first_difference: Option<(usize, String)>,
    /// the fixed delay from the planning tick's entry to its steps, cycles
    pub delay: i64,
    /// ticks not one tick length after the one before (a missed tick)
    pub gaps: usize,
    /// the step timer's window, cycles
    pub tick_len: u64,
}

impl Replay {
    pub fn equal(&self) -> bool {
        self.ticks > 0
            && self.enable_differs == 0
            && self.gaps == 0
            && self.planned == self.rises
            && self.planned > 0
            && self.first_difference.is_none()
            && self.delay_is_the_pipelines()
    }

    /// A plan runs two ticks after the tick that made it (`steps::pipe`); the
    /// delay is counted from the handler's entry, which comes the interrupt's
    /// entry latency (well under 100 cycles) after the tick's instant. The
    /// arm's copy of TIM11's count into TIM1's (`program::arm`'s `Sync`) adds
    /// `SYNC_CYCLES` for the read-to-write distance it takes on silicon; here
    /// both accesses of a block see one instant, so the steps come up to that
    /// much later.
    pub fn delay_is_the_pipelines(&self) -> bool {
        let two = 2 * self.tick_len as i64;
        let sync = polyturn_firmware::stepgen::program::SYNC_CYCLES as i64;
        (two - 100..=two + sync).contains(&self.delay)
    }
}

/// Rising edges of STEP (PA8) with DIR (PA9) as it stood, `dir` before the first.
fn rises(edges: &[Edge], mut dir: bool, until: u64) -> Vec<(u64, bool)> {
    let mut out = Vec::new();
    let mut step = false;
    for e in edges.iter().take_while(|e| e.cycle < until) {
        match e.pin {
            PinId::Pa8 if e.high && !step => out.push((e.cycle, dir)),
            PinId::Pa9 => dir = e.high,
            _ => {}
        }
        if e.pin == PinId::Pa8 {
            step = e.high;
        }
    }
    out
}

/// The host core's steps for the ticks on `tape` entered before `until`:
/// (cycle from the first tick's entry, forward), and the ticks' ENABLE.
fn plan(config: &Config, tape: &Tape, until: u64) -> (Vec<(u64, bool)>, usize, usize) {
    let mut core = Controller::new(*config, Timing::FIRMWARE);
    let (l, e, c) = tape.start;
    core.start(l, e, c);
    if let Some(clock) = tape.edge_clock {
        core.start_edges(clock);
    }
    let len = core.derived().steps.tick_len as u64;
    let (mut steps, mut differs, mut n) = (Vec::new(), 0, 0);
    let mut commands = tape.commands.iter().peekable();
    for (k, t) in tape.ticks.iter().take_while(|t| t.at < until).enumerate() {
        while let Some((_, c)) = commands.next_if(|c| c.0 <= k) {
            match c {
                Command::Engage => drop(core.engage()),
                Command::Disengage => core.disengage(),
                // the service task's; a no-op unless a re-base is pending
                Command::Rebase => core.service(),
            }
        }
        let out = core.tick(&t.input);
        differs += (out.enable != t.enable) as usize;
        for i in 0..out.plan.count as u32 {
            steps.push((k as u64 * len + out.plan.at(i) as u64, out.plan.dir == Dir::Forward));
        }
        n += 1;
    }
    (steps, differs, n)
}

/// Replays `tape` through the host core and lays its steps over `edges`.
pub fn compare(config: &Config, tape: &Tape, edges: &[Edge], until: u64) -> Replay {
    let (host, enable_differs, ticks) = plan(config, tape, until);
    let image = rises(edges, true, until);
    let len = polyturn_sync::derived::Derived::new(config, Timing::FIRMWARE).steps.tick_len as u64;
    let first_at = tape.ticks.first().map_or(0, |t| t.at);
    let gaps =
        tape.ticks.windows(2).take_while(|w| w[1].at < until).filter(|w| w[1].at - w[0].at > len * 3 / 2).count();
    let offset = match (image.first(), host.first()) {
        (Some(i), Some(h)) => i.0 as i64 - h.0 as i64,
        _ => 0,
    };
    // the last ticks' plans run after `until` (two ticks on): compare the
    // steps both sides put before it
    let host: Vec<(u64, bool)> = host.into_iter().filter(|h| h.0 as i64 + offset < until as i64).collect();
    let first_difference = host.iter().zip(&image).enumerate().find_map(|(j, (h, i))| {
        let want = h.0 as i64 + offset;
        (want != i.0 as i64 || h.1 != i.1).then(|| {
            (j, format!("rise {j}: the host plans cycle {want} {}, the image rose at {} {}", way(h.1), i.0, way(i.1)))
        })
    });
    Replay {
        ticks,
        enable_differs,
        planned: host.len(),
        rises: image.len(),
        first_difference,
        delay: offset - first_at as i64,
        gaps,
        tick_len: len,
    }
}

fn way(forward: bool) -> &'static str {
    if forward {
        "forward"
    } else {
        "reverse"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chip::tape::TickSeen;
    use polyturn_sync::TickInput;

    fn edge(cycle: u64, pin: PinId, high: bool) -> Edge {
        Edge { cycle, pin, high }
    }

    #[test]
    fn a_rise_takes_the_dir_level_set_before_it_and_edges_from_until_on_are_left_out() {
        let e = [
            edge(10, PinId::Pa8, true),
            edge(20, PinId::Pa8, false),
            edge(30, PinId::Pa9, false),
            edge(40, PinId::Pa8, true),
            edge(50, PinId::Pa8, false),
            edge(60, PinId::Pa8, true),
        ];
        assert_eq!(rises(&e, true, 60), vec![(10, true), (40, false)]);
    }

    #[test]
    fn an_idle_tape_is_not_called_equal_and_a_step_the_host_did_not_plan_is_found() {
        let config = Config::default();
        let idle = TickSeen { at: 0, input: TickInput::default(), enable: false, edge_read_at: None };
        let mut tape = Tape::default();
        let len = polyturn_sync::derived::Derived::new(&config, Timing::FIRMWARE).steps.tick_len as u64;
        tape.ticks = (0..10).map(|k| TickSeen { at: k * len, ..idle }).collect();
        let r = compare(&config, &tape, &[], u64::MAX);
        assert_eq!((r.ticks, r.planned, r.rises), (10, 0, 0));
        assert!(!r.equal(), "nothing planned, nothing compared");
        let r = compare(&config, &tape, &[edge(5, PinId::Pa8, true)], u64::MAX);
        assert_eq!(r.rises, 1);
        assert!(!r.equal());
    }
}
