//! Once a second over defmt: lathe and cutter rpm, phase error, tick cost,
//! and two of the lathe's timed edges in a row (the bench's check of the
//! edge registers, docs/src/bench.md).

use super::tick;
use defmt::info;
use embassy_time::Timer;
use polyturn_sync::edges::EdgeRegs;

/// Polls for the next timed edge: every `EDGE_POLL_US`, `EDGE_POLLS` times
/// (5 ms: A at 200 Hz or faster; consecutive rises up to A at 20 kHz).
const EDGE_POLL_US: u64 = 50;
const EDGE_POLLS: u32 = 100;

/// The last timed edge now, the next one after it, and k0 mod 4; `None` if
/// no edge is timed, none came since the last call (`seen`: the lathe at
/// rest is not polled), or none within the polls.
async fn edge_pair(seen: &mut Option<EdgeRegs>) -> Option<(EdgeRegs, EdgeRegs, u16)> {
    let (first, k0) = tick::last_edge()?;
    if seen.replace(first) == Some(first) {
        return None;
    }
    for _ in 0..EDGE_POLLS {
        Timer::after_micros(EDGE_POLL_US).await;
        let (next, _) = tick::last_edge()?;
        if next.stamp != first.stamp {
            return Some((first, next, k0));
        }
    }
    None
}

#[embassy_executor::task]
pub async fn every_second() {
    let mut checked = false;
    let mut edge_seen = None;
    let (mut tick_seen, mut plan_seen) = (Default::default(), Default::default());
    loop {
        Timer::after_millis(1000).await;
        // again once everything is up (USB, the self-test's timer and the
        // planning executor enable their interrupts after boot's check)
        if !core::mem::replace(&mut checked, true) && !super::priorities::check() {
            defmt::error!("an interrupt reaches the tick's or its step plan's level: fix board::PRIORITIES");
        }
        let ends = |l: &polyturn_firmware::latency::Latency, seen: &mut polyturn_firmware::latency::Counts| {
            let now = l.counts();
            let d = now.since(seen);
            *seen = now;
            d
        };
        let (tick_end, plan_end) = (ends(&tick::TICK_END, &mut tick_seen), ends(&tick::PLAN_END, &mut plan_seen));
        // defmt-rtt holds the critical section for a whole line (80 µs,
        // `cs.rs`), which would hold off the self-test's TIM9 interrupt
        // past its index deadline (`quadgen`): no report while it runs
        if super::selftest::playing() {
            continue;
        }
        // Copy under the lock, format outside it (the tick shares the lock).
        if let Some(snap) = tick::with_core(|c| polyturn_sync::console::Snapshot::of(c)) {
            let mut line = polyturn_sync::console::Reply::new();
            snap.write(&mut line);
            let late = tick::steps_late();
            // the bench's figure (bench.md): when the step plan ends, in
            // cycles after its tick's instant, by sixteenths of the period
            info!(
                "{} | {} ticks; the tick ends by {} cycles at worst, its step plan by {} (of {}), histogram {} per {} cycles, {} after the next tick ({} not written when it began); step segments late {}, NDTR lead {}",
                line.as_str(),
                tick::ticks(),
                tick_end.worst,
                plan_end.worst,
                tick::PERIOD,
                plan_end.bins,
                tick::PERIOD / polyturn_firmware::latency::BINS as u32,
                plan_end.late,
                tick::plans_past_next(),
                late,
                tick::ndtr_lead()
            );
        }
        if let Some((a, b, k0)) = edge_pair(&mut edge_seen).await {
            // CCR1 − k0 mod 4, A rising while counting up: 0 if the capture
            // takes the count before its edge's, 1 after (3 and 2 counting
            // down); the next rise's µs and counts (±4: A's period)
            info!(
                "edge: CCR1 {} ({} past A,B low), CCR3 {} us; next rise {} us later, {} counts on",
                a.count,
                a.count.wrapping_sub(k0) & 3,
                a.stamp,
                b.stamp.wrapping_sub(a.stamp),
                b.count.wrapping_sub(a.count) as i16
            );
        }
    }
}
