use super::*;

const T: u64 = STAMPS_PER_TICK as u64;

/// The board as a look finds it at real time `r` µs: instants every tick
/// from 0, each tick running `latency` µs after its instant, but the ticks
/// of `dropped` never running: their update stays pending (UIF) until the
/// next one's tick answers both. Returns what `next_instant` measures, `skew`
/// µs off (the latest update's instant while one is pending, TIM11 counting
/// from it; else the next), and the ticks run, from `base` at r = 0.
fn board(r: f64, latency: f64, dropped: &[u64], skew: i64, base: u32) -> (u16, u32) {
    let last = (r / T as f64) as u64;
    let answered = |j: u64| {
        let by = if dropped.contains(&j) { (j + 1) * T } else { j * T };
        r >= by as f64 + latency
    };
    let ran = (0..=last).filter(|&j| !dropped.contains(&j) && answered(j)).count() as u32;
    let pending = (0..=last).any(|j| !answered(j));
    let next = if pending { last * T } else { (last + 1) * T };
    ((next as i64 + skew) as u64 as u16, base.wrapping_add(ran))
}

#[test]
fn on_time_nothing_is_lost_wherever_in_a_tick_it_looks() {
    for latency in [0.6, 3.0, 12.0, T as f64 - 1.0] {
        let (n0, k0) = board(0.3, latency, &[], 0, 500);
        let mut w = Watch::new(n0, k0);
        // a look every 0.7 µs over 2 000 ticks (the stamps wrap past 65 536)
        for tenth in (7..(2_000 * T * 10)).step_by(7) {
            let r = tenth as f64 / 10.0;
            let (n, k) = board(r, latency, &[], 0, 500);
            assert_eq!(w.look(n, k), Some(0), "at {r} µs, latency {latency}");
        }
    }
}

#[test]
fn a_dropped_tick_is_counted_once_at_the_next_look_after_it() {
    for latency in [0.6, 12.0, T as f64 - 1.0] {
        let mut w = Watch::new(board(0.0, latency, &[10], 0, 7).0, 7);
        let mut counted = 0;
        for ms_tenth in 1..(60 * T) {
            let r = ms_tenth as f64 * 1.3;
            let (n, k) = board(r, latency, &[10], 0, 7);
            let lost = w.look(n, k).unwrap();
            counted += lost;
            // counted when the look finds tick 11's run (or pending) past it
            if r >= (11 * T) as f64 + latency {
                assert_eq!(counted, 1, "at {r} µs, latency {latency}");
            }
        }
        assert_eq!(counted, 1, "latency {latency}");
    }
}

#[test]
fn a_measurement_a_stamp_off_either_way_neither_makes_nor_hides_a_loss() {
    let skews = [1i64, -1, 0, 1, 1, -1, 0, -1];
    for turn in 0..skews.len() {
        let skew = |k: u64| skews[(k as usize + turn) % skews.len()];
        let (n0, k0) = board(5.0, 2.0, &[250], skew(0), 100);
        let mut w = Watch::new(n0, k0);
        let mut counted = 0;
        for k in 1..500u64 {
            let (n, ran) = board((k * T) as f64 + 5.0, 2.0, &[250], skew(k), 100);
            counted += w.look(n, ran).unwrap();
            assert_eq!(counted, (k > 250) as u32, "look {k}, turn {turn}");
        }
    }
}

#[test]
fn the_tick_count_wraps_without_a_false_loss() {
    // 2^32 ticks run: the counts between looks are what count
    let mut w = Watch::new(1_000, u32::MAX - 2);
    assert_eq!(w.look(1_000 + 10 * T as u16, 7), Some(0));
    assert_eq!(w.look(1_000 + 20 * T as u16, 16), Some(1));
}

#[test]
fn looks_half_the_wrap_apart_are_not_judged_and_the_next_judges_from_the_later() {
    let mut w = Watch::new(0, 0);
    // 33 ms on, a tick short: too far to tell
    assert_eq!(w.look(825 * T as u16, 824), None);
    assert_eq!(w.look(826 * T as u16, 825), Some(0));
    assert_eq!(w.look(828 * T as u16, 826), Some(1));
}
