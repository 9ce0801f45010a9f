use super::*;

const T: u64 = STAMPS_PER_TICK as u64;
/// The instant the watch is anchored on (its stamp the low 16 bits).
const AT: u64 = 1_000_037;

/// What the service reads at real time `r` µs (the clock shows its whole
/// µs) when each instant's update comes 0.5 µs into its µs and its tick
/// has run `latency` µs after the instant, the ticks of `dropped` never
/// running (absorbed into the next one's pending interrupt): (ticks run,
/// UIF pending). 500 ticks ran before `AT`.
fn read(r: f64, latency: f64, dropped: &[u64]) -> (u32, bool) {
    let (mut ran, mut pending) = (500u32, false);
    for j in 0..=((r - AT as f64) / T as f64).max(0.0) as u64 + 1 {
        let at = (AT + j * T) as f64;
        if r >= at + latency {
            ran += !dropped.contains(&j) as u32;
        } else if r >= at + 0.5 {
            pending = true;
        }
    }
    (ran, pending)
}

#[test]
fn on_time_nothing_is_lost_wherever_in_a_tick_the_service_reads() {
    // anchored 7 µs before the instant, as the start measures it
    let w = Watch::anchor(AT as u16, AT - 7, 500);
    for latency in [0.6, 3.0, 12.0, 39.0] {
        for tenth in 0..(200 * T * 10) {
            let r = AT as f64 - 3.0 + tenth as f64 / 10.0;
            let (ran, pending) = read(r, latency, &[]);
            assert_eq!(w.lost(r as u64, ran, pending), 0, "at {r} µs, latency {latency}");
        }
    }
}

#[test]
fn a_tick_that_never_ran_is_counted_from_the_next_tick_on() {
    let w = Watch::anchor(AT as u16, AT - 7, 500);
    for latency in [0.6, 12.0, 39.0] {
        for tenth in 0..(30 * T * 10) {
            let r = AT as f64 + tenth as f64 / 10.0;
            let (ran, pending) = read(r, latency, &[10]);
            let lost = w.lost(r as u64, ran, pending);
            assert!(lost <= 1, "at {r} µs, latency {latency}");
            if r < (AT + 10 * T) as f64 + latency {
                assert_eq!(lost, 0, "before tick 10 was due: {r} µs");
            }
        }
        // in the middle of every tick from the next one on: seen
        for k in 11..30 {
            let r = (AT + k * T) as f64 + 20.3;
            let (ran, pending) = read(r, latency, &[10]);
            assert_eq!(w.lost(r as u64, ran, pending), 1, "tick {k}, latency {latency}");
        }
    }
}

#[test]
fn the_anchor_takes_an_instant_behind_the_clock_when_its_tick_is_pending() {
    // an instant 3 µs ago whose tick is pending: 41 ticks have run, that
    // one makes 42
    let now = (1u64 << 16) + 5_003;
    let w = Watch::anchor(5_000, now, 41);
    assert_eq!(w, Watch { instant_us: now - 3, ticks_after: 42 });
    assert_eq!(w.lost(now, 41, true), 0);
    assert_eq!(w.lost(now, 41, false), 1, "no tick and none pending: lost");
}

#[test]
fn the_stamp_and_the_tick_count_wrap_without_a_false_loss() {
    // an instant at stamp 0xFFF0 read 20 µs later, past the wrap; its tick
    // takes the count from u32::MAX to 0
    let now = (3u64 << 16) + 4;
    let w = Watch::anchor(0xFFF0, now, u32::MAX);
    assert_eq!(w.instant_us, (3u64 << 16) - 16);
    assert_eq!(w.lost(now + 100 * T, 100, false), 0, "{w:?}");
    assert_eq!(w.lost(now + 100 * T, 99, false), 1);
}

#[test]
fn before_its_instant_nothing_is_lost() {
    let w = Watch::anchor(AT as u16, AT - 7, 500);
    assert_eq!(w.lost(AT - 1, 500, false), 0);
    assert_eq!(w.lost(AT, 500, false), 0, "the instant's own µs: its update may be coming");
    assert_eq!(w.lost(0, 0, false), 0);
}
