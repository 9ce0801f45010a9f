use super::*;

const NONE: [bool; 4] = [false; 4];

fn only(k: Key) -> [bool; 4] {
    let mut p = NONE;
    p[k as usize] = true;
    p
}

/// Runs `levels(ms)` for `ms` in 0..span, one sample a millisecond, and
/// returns every non-empty event with its time.
fn run(span: u32, levels: impl Fn(u32) -> [bool; 4]) -> Vec<(u32, Events)> {
    let mut keys = Keys::default();
    (0..span).map(|ms| (ms, keys.sample(ms, levels(ms)))).filter(|(_, e)| *e != Events::default()).collect()
}

#[test]
fn a_clean_press_counts_once_after_the_debounce_time() {
    let ev = run(3_000, |ms| if (100..2_000).contains(&ms) { only(Key::Engage) } else { NONE });
    assert_eq!(ev, vec![(100 + DEBOUNCE_MS, Events { engage: true, ..Events::default() })]);
}

#[test]
fn contact_bounce_at_press_and_release_gives_one_press() {
    // 8 ms of bounce (2 ms on, 2 ms off) on both edges of a 300 ms press
    let bouncy = |ms: u32| {
        let bouncing = (100..108).contains(&ms) || (400..408).contains(&ms);
        let down = if bouncing { ms % 4 < 2 } else { (108..400).contains(&ms) };
        if down {
            only(Key::Engage)
        } else {
            NONE
        }
    };
    let ev = run(1_000, bouncy);
    assert_eq!(ev.len(), 1, "{ev:?}");
    assert!(ev[0].1.engage);
}

#[test]
fn a_chattering_key_never_counts() {
    // a key (or a noisy wire) that changes every 7 ms never settles
    for k in [Key::Engage, Key::Stop, Key::PhasePlus, Key::PhaseMinus] {
        let ev = run(5_000, |ms| if (ms / 7) % 2 == 0 { only(k) } else { NONE });
        assert!(ev.is_empty(), "{k:?}: {ev:?}");
    }
}

#[test]
fn a_held_engage_engages_once() {
    let ev = run(10_000, |ms| if ms >= 50 { only(Key::Engage) } else { NONE });
    assert_eq!(ev.iter().filter(|(_, e)| e.engage).count(), 1);
}

#[test]
fn a_held_stop_repeats_and_holds_off_engage() {
    let both = |ms: u32| {
        let mut p = NONE;
        p[Key::Stop as usize] = ms >= 100;
        p[Key::Engage as usize] = ms >= 600;
        p
    };
    let ev = run(2_000, both);
    assert!(ev.iter().all(|(_, e)| !e.engage), "ENGAGE acted while STOP was held");
    let stops: Vec<u32> = ev.iter().filter(|(_, e)| e.stop).map(|(t, _)| *t).collect();
    // the press at 120 ms, then every 250 ms while held
    assert_eq!(stops, vec![120, 370, 620, 870, 1120, 1370, 1620, 1870]);
}

#[test]
fn phase_keys_nudge_per_press_then_repeat_while_held() {
    let ev = run(1_300, |ms| if ms >= 100 { only(Key::PhasePlus) } else { NONE });
    let t: Vec<u32> = ev.iter().filter(|(_, e)| e.phase == 1).map(|(t, _)| *t).collect();
    assert_eq!(t, vec![120, 620, 870, 1120]);
    let down = run(400, |ms| if ms >= 100 { only(Key::PhaseMinus) } else { NONE });
    assert_eq!(down, vec![(120, Events { phase: -1, ..Events::default() })]);
}

#[test]
fn both_phase_keys_or_stop_held_nudge_nothing() {
    let both = |_: u32| [false, false, true, true];
    assert!(run(2_000, both).is_empty());
    let with_stop = |_: u32| [false, true, true, false];
    assert!(run(2_000, with_stop).iter().all(|(_, e)| e.phase == 0));
}

#[test]
fn the_millisecond_clock_may_wrap_under_a_press() {
    let mut keys = Keys::default();
    let start = u32::MAX - 100;
    let mut engaged = 0;
    for i in 0..300u32 {
        let level = if i < 90 { NONE } else { only(Key::Engage) };
        engaged += keys.sample(start.wrapping_add(i), level).engage as u32;
    }
    assert_eq!(engaged, 1);
}

#[test]
fn a_nudge_past_a_whole_turn_is_refused_not_wrapped() {
    assert_eq!(nudged_phase(0, 1), Some(1_000));
    assert_eq!(nudged_phase(359_000, 1), Some(360_000));
    // wrapping to 0.5 would swing the cutter 359 degrees back mid-cut
    assert_eq!(nudged_phase(359_500, 1), None);
    assert_eq!(nudged_phase(-359_500, -1), None);
    assert_eq!(nudged_phase(-500, 1), Some(500));
}

#[test]
fn a_key_down_at_power_up_does_nothing_until_released() {
    // ENGAGE held (or shorted) through a reset
    let held = run(5_000, |_| only(Key::Engage));
    assert!(held.is_empty(), "{held:?}");
    let stop_held = run(5_000, |_| only(Key::Stop));
    assert!(stop_held.is_empty(), "{stop_held:?}");
    // a STOP down since power-up still holds ENGAGE off
    let both = run(2_000, |ms| if ms < 500 { only(Key::Stop) } else { [true, true, false, false] });
    assert!(both.iter().all(|(_, e)| !e.engage), "{both:?}");
    // released, then pressed: counts
    let again = run(2_000, |ms| if !(100..1_000).contains(&ms) { only(Key::Engage) } else { NONE });
    assert_eq!(again.iter().filter(|(_, e)| e.engage).count(), 1);
}
