use super::motion::{check, MotionError};
use super::*;
use crate::controller::{check_table, prepare_cam};
use crate::{Config, Controller, Timing};
use std::format;
use std::vec::Vec;

/// A header for `points` over one turn of a 2 400-count encoder, its X
/// axis at the board's top rate (`X_MAX_RATE_HZ`) and 10^6 steps/s².
fn header(points: usize) -> CamHeader {
    CamHeader {
        points: points as u32,
        period_counts: 2_400,
        counts_per_rev: 2_400,
        max_rate_hz: X_MAX_RATE_HZ,
        max_accel: 1_000_000,
    }
}

/// 1 024 points of a 1 mm (800-step) wave: what `polyturn cam` makes.
fn smooth() -> Vec<i32> {
    (0..1024).map(|i| ((i as f64 / 1024.0 * core::f64::consts::TAU).sin() * 800.0).round() as i32).collect()
}

#[test]
fn a_smooth_table_is_taken() {
    assert_eq!(check(&header(1024), &smooth()), Ok(()));
    assert_eq!(check_table(&header(1024), &smooth()), Ok(()));
}

/// 125 mm at 800 steps/mm between two neighbours: at 1 rpm of a 2 400-count
/// lathe a segment (2 400 / 1 024 counts) lasts 60 / 1 024 s, so the jump
/// needs (100 000 - 1) x 1 024 / 60 X steps/s.
#[test]
fn a_jump_between_neighbours_no_x_axis_can_make_is_refused_with_its_figures() {
    let mut points = smooth();
    points[500] += 100_000;
    let e = check(&header(1024), &points).unwrap_err();
    let apart = (points[500] - points[499]).max(points[500] - points[501]) as u32;
    let needs_hz = ((apart as u64 - 1) * 1024).div_ceil(60);
    assert_eq!(e, MotionError::Rate { span: 1, apart, needs_hz, max_hz: X_MAX_RATE_HZ });
    assert_eq!(
        format!("{e}"),
        format!("cam table: neighbouring points {apart} steps apart need {needs_hz} X steps/s at 1 lathe rpm, beyond its max-rate {X_MAX_RATE_HZ} steps/s (a table must be followed at 1 rpm or faster)")
    );
    assert_eq!(check_table(&header(1024), &points), Err(TableRefusal::Motion(e)));
    let leaked: &'static [i32] = Vec::leak(points);
    assert_eq!(prepare_cam(&header(1024), leaked, Timing::FIRMWARE).err(), Some(e.describe()));
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    assert_eq!(c.fit_cam(&header(1024), leaked).err(), Some(e.describe()));
    assert!(c.x_axis().is_none(), "nothing fitted");
}

/// Two points over a turn: a segment is 1 200 counts, 30 s at 1 rpm. The
/// step is d - 1 steps (a step is the rounding's) over 30 s.
#[test]
fn the_rate_is_taken_up_to_its_limit_and_the_rounding_is_allowed_for() {
    let h = CamHeader { max_rate_hz: 100, max_accel: 1_000, ..header(2) };
    assert_eq!(check(&h, &[0, 3_001]), Ok(()), "3 000 steps in 30 s: 100 steps/s");
    assert_eq!(check(&h, &[0, 3_002]), Err(MotionError::Rate { span: 1, apart: 3_002, needs_hz: 101, max_hz: 100 }));
    assert_eq!(check(&h, &[5, 6]), Ok(()), "a step of rounding");
}

/// A zigzag of 100 steps between neighbours, within the rate (99 x 1 024
/// / 60 = 1 690 steps/s) but bending by 200 steps at each point: 198 x
/// (1 024 / 60)^2 steps/s² at 1 rpm.
#[test]
fn a_bend_sharper_than_the_x_axis_accelerates_is_refused_with_its_figures() {
    let zigzag: Vec<i32> = (0..1024).map(|i| if i % 2 == 0 { 0 } else { 100 }).collect();
    let h = CamHeader { max_accel: 10_000, ..header(1024) };
    let needs = (198u64 * 1024 * 1024).div_ceil(3_600);
    assert_eq!(needs, 57_672);
    let e = check(&h, &zigzag).unwrap_err();
    assert_eq!(e, MotionError::Accel { span: 1, bend: 200, needs, max: 10_000 });
    assert!(format!("{e}").starts_with("cam table: a bend of 200 steps at a point needs 57672 X steps/s^2 at 1 lathe rpm, beyond its max-accel 10000 steps/s^2"), "{e}");
    assert_eq!(check(&CamHeader { max_accel: 57_672, ..h }, &zigzag), Ok(()));
}

/// The table wraps: the step from the last point back to the first counts.
#[test]
fn the_step_from_the_last_point_to_the_first_counts() {
    let ramp: Vec<i32> = (0..1024).map(|i| i * 4).collect();
    let e = check(&header(1024), &ramp).unwrap_err();
    assert!(matches!(e, MotionError::Rate { span: 1, apart: 4_092, .. }), "{e:?}");
}

/// Fine encoders, coarse tables: the products stay within 128 bits and the
/// figures saturate rather than wrap.
#[test]
fn extreme_headers_give_figures_not_overflows() {
    let h =
        CamHeader { points: 2, period_counts: 2, counts_per_rev: u32::MAX, max_rate_hz: u32::MAX, max_accel: u32::MAX };
    let e = check(&h, &[i32::MIN, i32::MAX]).unwrap_err();
    assert!(matches!(e, MotionError::Rate { apart: u32::MAX, max_hz: u32::MAX, .. }), "{e:?}");
    let h = CamHeader { period_counts: 0, ..h };
    assert!(check(&h, &[0, 0]).is_ok());
}

/// The reasons without figures, as the stored table's check at boot gives
/// them: each names the limit the points exceed.
#[test]
fn each_motion_refusal_describes_the_limit_it_exceeds() {
    let rate = MotionError::Rate { span: 1, apart: 2, needs_hz: 3, max_hz: 1 };
    let accel = MotionError::Accel { span: 4, bend: 2, needs: 3, max: 1 };
    assert_eq!(rate.describe(), "cam table: its points need more than its max-rate even at 1 lathe rpm");
    assert_eq!(accel.describe(), "cam table: its points need more than its max-accel even at 1 lathe rpm");
}

/// A dense table moves a step or less between neighbours, all within the
/// rounding's allowance at span 1. 1 024 points of a 1 mm wave (800 steps)
/// over one turn: at 1 rpm its path peaks at 800 · 2π / 60 = 83.8 steps/s
/// and 800 · (2π / 60)² = 8.77 steps/s², which the spans find (each a lower
/// bound, the rounding taken off), so an axis declared slower or weaker
/// than that is refused.
#[test]
fn a_dense_table_is_measured_over_spans_so_a_slow_axis_is_refused() {
    let wave = smooth();
    let (d1, d2) =
        wave.windows(3).fold((0, 0), |(a, b), w| (a.max((w[1] - w[0]).abs()), b.max((w[2] - 2 * w[1] + w[0]).abs())));
    assert!(d1 <= 5 && d2 <= 2, "neighbours alone show no motion past the rounding: {d1} {d2}");
    let e = check(&CamHeader { max_rate_hz: 60, ..header(1024) }, &wave).unwrap_err();
    let MotionError::Rate { span, needs_hz, .. } = e else { panic!("{e:?}") };
    assert!(span > 1 && (70..=84).contains(&needs_hz), "{e:?}");
    assert!(format!("{e}").starts_with(&format!("cam table: points {span} apart move ")), "{e}");
    assert_eq!(
        check(&CamHeader { max_rate_hz: 84, max_accel: 8, ..header(1024) }, &wave)
            .map_err(|e| matches!(e, MotionError::Accel { .. })),
        Err(true)
    );
    let e = check(&CamHeader { max_rate_hz: 84, max_accel: 5, ..header(1024) }, &wave).unwrap_err();
    let MotionError::Accel { span, needs, .. } = e else { panic!("{e:?}") };
    assert!(span > 1 && (6..=9).contains(&needs), "{e:?}");
    assert_eq!(
        check(&CamHeader { max_rate_hz: 84, max_accel: 9, ..header(1024) }, &wave),
        Ok(()),
        "what the path needs is taken"
    );
}

/// A table whose every point is within a step of its neighbour but which
/// climbs 1 000 steps in a turn and falls back: the climb over the longest
/// span is the speed.
#[test]
fn a_ramp_of_single_steps_is_a_speed_over_its_span() {
    let tri: Vec<i32> = (0..1024).map(|i: i32| if i < 512 { i * 2 } else { (1024 - i) * 2 }).collect();
    let h = CamHeader { max_rate_hz: 10, max_accel: u32::MAX, ..header(1024) };
    // 2 steps a segment, a segment 60 / 1 024 s: 34.1 steps/s, the spans'
    // (512 · 2 − 1) / 30 s = 34.1
    let e = check(&h, &tri).unwrap_err();
    assert!(matches!(e, MotionError::Rate { needs_hz: 34 | 35, .. }), "{e:?}");
    assert_eq!(check(&CamHeader { max_rate_hz: 35, ..h }, &tri), Ok(()));
}

/// Spans that need the same are told by the shortest: four points over a
/// turn, at 1 rpm a segment 15 s. [0, 2, 4, 2]: 2 steps a segment (one of
/// rounding) and 4 over two (three of motion) both need 1 step/s, once
/// rounded up; bends of 4 at a point and 8 over two points both 1 step/s².
/// An axis of 0 is refused by span 1, with its figures.
#[test]
fn spans_that_need_the_same_are_told_by_the_shortest_and_span_two_counts() {
    let h = CamHeader { max_rate_hz: 0, max_accel: 0, ..header(4) };
    assert_eq!(check(&h, &[0, 2, 4, 2]), Err(MotionError::Rate { span: 1, apart: 2, needs_hz: 1, max_hz: 0 }));
    let h = CamHeader { max_rate_hz: 1, ..h };
    assert_eq!(check(&h, &[0, 2, 4, 2]), Err(MotionError::Accel { span: 1, bend: 4, needs: 1, max: 0 }));
    // [0, 1, 2, 1]: neighbours a step apart need nothing; two apart, 1 step/s
    let h = CamHeader { max_rate_hz: 0, max_accel: u32::MAX, ..header(4) };
    assert_eq!(check(&h, &[0, 1, 2, 1]), Err(MotionError::Rate { span: 2, apart: 2, needs_hz: 1, max_hz: 0 }));
}
