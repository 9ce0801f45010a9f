//! The judge on its own: samples made up to the point each rule decides.

use super::*;

fn plan() -> Plan {
    Plan::new(300, 2400, 1_000)
}

/// A sample that passes every rest check, `ms` into the profile.
fn good(ms: u32, counts: i64) -> (Books, Seen) {
    let b = Books { counts, indexes: 3, ms, running: true, last_index: Some(2401), latency_cycles: 300 };
    let s = Seen {
        state: State::Synced,
        counts,
        indexes: 3,
        last_index: 2401,
        lag_q16: 0,
        off_q16: 0,
        cutter_steps: 10,
        target_steps: 10,
        exact_steps: 10,
        overdue: false,
    };
    (b, s)
}

#[test]
fn the_profile_rests_ramps_holds_and_comes_back() {
    let p = plan();
    assert_eq!(p.total_ms(), 2_000 + 4 * 1_000 + 2 * 2_000 + 2 * 600);
    let kinds: [Kind; LEGS] = p.legs.map(|l| l.kind);
    use Kind::*;
    assert_eq!(kinds, [Rest, Ramp, Hold, Ramp, Rest, Ramp, Hold, Ramp, Rest]);
    assert_eq!((p.legs[2].from_rpm, p.legs[6].to_rpm), (300, -300));
    assert_eq!((p.leg_at(0), p.leg_at(1_999), p.leg_at(2_000), p.leg_at(99_999)), (0, 0, 1, 8));
    assert_eq!(p.end_of(0), 2_000);
    assert_eq!(p.end_of(8), p.total_ms());
}

#[test]
fn a_ramp_lasts_long_enough_for_half_the_acceleration_limit() {
    assert_eq!(plan::ramp_ms(32_000, 400_000), plan::MIN_RAMP_MS);
    // 32 000 steps/s at 10 000 steps/s²: 6.4 s at half the limit
    assert_eq!(plan::ramp_ms(32_000, 10_000), 6_400);
    assert_eq!(plan::rate_hz(300, 2400, 8, 3), 32_000);
}

#[test]
fn three_exact_rests_pass() {
    let mut t = SelfTest::new(plan());
    for (i, ms) in [1_950, 6_550, 11_150].into_iter().enumerate() {
        assert!(t.running());
        let (b, s) = good(ms, 0);
        t.sample(&b, &s);
        assert_eq!(t.report().rests, i as u8 + 1);
    }
    assert_eq!(t.report().verdict, Verdict::Pass);
}

#[test]
fn a_rest_is_checked_only_once_the_lathe_has_settled() {
    let mut t = SelfTest::new(plan());
    let (b, mut s) = good(1_850, 5);
    s.counts = 4; // still moving: not judged yet
    t.sample(&b, &s);
    assert_eq!((t.report().rests, t.report().verdict), (0, Verdict::Running));
    let (b, s) = good(1_900, 5);
    t.sample(&b, &s);
    assert_eq!(t.report().rests, 1);
}

/// Breaks one figure of a good sample.
type Break = fn(&mut Seen);

#[test]
fn each_rest_rule_fails_with_its_figures() {
    let cases: [(Break, Failure); 6] = [
        (|s| s.state = State::Engaging, Failure::NotSynced { rest: 1 }),
        (|s| s.counts = 7, Failure::Counts { rest: 1, seen: 7, made: 0 }),
        (|s| s.indexes = 2, Failure::Indexes { rest: 1, seen: 2, made: 3 }),
        (|s| s.last_index = 2402, Failure::IndexLate { rest: 1, seen: 2402, made: 2401 }),
        (|s| s.target_steps = 11, Failure::Gear { rest: 1, target: 11, exact: 10 }),
        (|s| s.off_q16 = -(1 << 15) - 1, Failure::Cutter { rest: 1, off_q16: -(1 << 15) - 1 }),
    ];
    for (break_it, want) in cases {
        let mut t = SelfTest::new(plan());
        let (b, mut s) = good(1_950, 0);
        break_it(&mut s);
        t.sample(&b, &s);
        assert_eq!(t.report().verdict, Verdict::Fail(want));
    }
    // half a step off is still the nearest whole step
    let mut t = SelfTest::new(plan());
    let (b, mut s) = good(1_950, 0);
    s.off_q16 = 1 << 15;
    t.sample(&b, &s);
    assert_eq!(t.report().rests, 1);
}

#[test]
fn a_fault_a_stop_or_a_silent_generator_ends_it_at_once() {
    for (state, want) in [
        (State::Fault(Fault::EStop), Failure::Fault(Fault::EStop)),
        (State::Disengaging, Failure::Stopped),
        (State::Idle, Failure::Stopped),
    ] {
        let mut t = SelfTest::new(plan());
        let (b, mut s) = good(500, 0);
        s.state = state;
        t.sample(&b, &s);
        assert_eq!(t.report().verdict, Verdict::Fail(want));
    }
    let mut t = SelfTest::new(plan());
    t.sample(&good(1_950, 0).0, &good(1_950, 0).1);
    let (mut b, s) = good(3_000, 0);
    b.running = false;
    t.sample(&b, &s);
    assert_eq!(t.report().verdict, Verdict::Fail(Failure::Generator));
    // books that stop moving: the tick's clock ends it (`overdue`)
    let mut t = SelfTest::new(plan());
    let (b, mut s) = good(100, 0);
    t.sample(&b, &s);
    assert_eq!(t.report().verdict, Verdict::Running);
    s.overdue = true;
    t.sample(&b, &s);
    assert_eq!(t.report().verdict, Verdict::Fail(Failure::Generator));
}

#[test]
fn the_first_failure_is_kept_and_stop_does_not_overwrite_a_pass() {
    let mut t = SelfTest::new(plan());
    let (b, mut s) = good(1_950, 0);
    s.counts = 1;
    t.sample(&b, &s);
    t.stop();
    assert_eq!(t.report().verdict, Verdict::Fail(Failure::Counts { rest: 1, seen: 1, made: 0 }));
}

#[test]
fn lags_are_kept_apart_for_holds_and_ramps_and_holds_report_steps_against_target() {
    let mut t = SelfTest::new(plan());
    t.sample(&good(1_950, 0).0, &good(1_950, 0).1);
    let at = |ms: u32, lag: i64, cutter: i64, target: i64| {
        let (b, mut s) = good(ms, 0);
        (s.lag_q16, s.cutter_steps, s.target_steps) = (lag, cutter, target);
        (b, s)
    };
    for (ms, lag, cutter, target) in
        [(2_500, -9, 0, 0), (3_001, 4, 100, 101), (4_999, -5, 900, 899), (5_001, 1, 950, 950)]
    {
        let (b, s) = at(ms, lag, cutter, target);
        t.sample(&b, &s);
    }
    let r = t.report();
    assert_eq!((r.ramp_lag_q16, r.hold_lag_q16), (9, 5));
    assert_eq!(r.holds[0], (850, 849));
}

#[test]
fn a_pass_reports_the_counts_made_each_way() {
    // out 7200 counts by rest 2, back to 0 by rest 3
    let mut t = SelfTest::new(plan());
    for (ms, counts) in [(1_950, 0), (6_550, 7_200), (11_150, 0)] {
        let (b, s) = good(ms, counts);
        t.sample(&b, &s);
    }
    let r = t.report();
    assert_eq!((r.verdict, r.rests, r.forward, r.backward), (Verdict::Pass, 3, 7_200, -7_200));
}
