//! Each peer against what its source says it does.

use super::clough42::Clough42;
use super::didge::Didge;
use super::nanoels::NanoEls;

/// Core.h/StepperDrive.h: trunc(count · ratio), one transition per
/// interrupt, so a step at most every second interrupt (100 kHz), and DIR
/// one interrupt ahead of a step the other way.
#[test]
fn clough42_chases_the_truncated_target_a_step_every_second_interrupt() {
    let mut c = Clough42::new(8, 3, 1, false); // 2.67 steps a count
    let steps: Vec<Option<i32>> = (0..12).map(|_| c.tick(3)).collect();
    // DIR first (state 0 → 1), then step, end, step, …: 8 steps = trunc(3 · 8/3)
    let up: Vec<usize> = steps.iter().enumerate().filter(|(_, s)| **s == Some(1)).map(|(i, _)| i).collect();
    assert_eq!(up, vec![1, 3, 5, 7, 9, 11]);
    let mut c = Clough42::new(8, 3, -1, true);
    let down = (0..40).filter_map(|_| c.tick(3)).collect::<Vec<_>>();
    assert_eq!(down, vec![-1; 8], "trunc toward 0 of −8, no DIR tick for a step back from DIR low");
}

/// h5.ino moveAxis: speed ← trunc(speed + accel/speed) a step, one step a
/// pass once 1e6/speed − 5 µs have passed; the plateau is accel + 1.
#[test]
fn nanoels_ramps_by_accel_over_speed_to_its_plateau() {
    let mut n = NanoEls::new((2400, 1, 1, 2400), 800, 20_000); // a step a count
    let mut last = None;
    let mut gaps = Vec::new();
    for k in 0..3_000_000u64 {
        let t = k as f64 * 1e-6;
        if let Some((at, d)) = n.pass(t, 1_000_000) {
            assert_eq!(d, 1);
            if let Some(l) = last.replace(at) {
                gaps.push(at - l);
            }
        }
    }
    // the first gap at the speed after one step: 800 + trunc(20 000 · 1 250 µs)
    assert!((gaps[0] - (1.0 / 825.0 - 5e-6)).abs() < 1.5e-6, "{}", gaps[0]);
    let end = gaps[gaps.len() - 1];
    // 1e6/20001 − 5 µs, on the 1 µs loop: 45 µs
    assert!((end - 45e-6).abs() < 1.5e-6, "{end}");
}

/// gear.hpp: the Bresenham's level is round half up of count · N/D; as
/// bursts each edge fires what is due at once, predicted each step waits
/// for its crossing from A's last period.
#[test]
fn didge_steps_the_bresenham_at_each_edge_or_at_each_crossing() {
    let mut b = Didge::new(8, 3, 1, false);
    let mut p = Didge::new(8, 3, 1, true);
    let (mut nb, mut np) = (0usize, 0usize);
    for count in 1..=12i64 {
        let t = count as f64 * 0.5e-3; // an edge every 0.5 ms: A's period 2 ms
        let fired = b.edge(t, count, count % 4 == 1);
        assert!(fired.iter().all(|s| s.0 >= t && s.0 < t + 1e-5), "bursts fire at the edge");
        nb += fired.len();
        assert_eq!(nb as i64, (2 * count * 8 + 3) / 6, "round half up of {count}·8/3");
        let scheduled = p.edge(t, count, count % 4 == 1);
        np += scheduled.len();
        if count > 5 {
            // with a period: the levels crossed before the next edge, each
            // at its crossing (level·3/8 counts)
            assert_eq!(np as i64, ((count + 1) * 8 - 1) / 3);
            for (k, s) in scheduled.iter().enumerate() {
                let level = (np - scheduled.len() + k + 1) as f64;
                let at = (level * 3.0 / 8.0) * 0.5e-3;
                assert!((s.0 - at).abs() < 1e-9, "level {level}: {} against {at}", s.0);
            }
        }
    }
}
