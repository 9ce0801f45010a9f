use super::*;
use crate::geometry::Direction;
use polyturn_sync::Ratio;

fn setup(ratio: &str, edges: u32, dir: Direction) -> Setup {
    Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 2.0,
        ratio: Ratio::parse(ratio).unwrap(),
        edges,
        direction: dir,
    }
}

#[test]
fn compensation_cuts_straight_flats_where_the_fixed_axis_cuts_curved_ones() {
    for (ratio, edges, dir) in [("3", 2, Direction::Same), ("1", 4, Direction::Same), ("2", 3, Direction::Same)] {
        let s = setup(ratio, edges, dir);
        let before = Section::ideal(&s, 2048).summary().flat_deviation;
        let p = plan(&s, 60.0, 1e9, 1e12);
        assert_eq!(p.limited_by, None, "{ratio} x {edges}: {:?}", p.limited_by);
        let after = section(&s, &p, 2048).summary();
        assert!(after.flat_deviation.abs() < 0.002, "{ratio} x {edges}: {} mm (was {before})", after.flat_deviation);
        assert!(before.abs() > 5.0 * after.flat_deviation.abs().max(1e-4), "{ratio} x {edges}: was already flat");
        assert!((after.inscribed_radius - 8.0).abs() < 1e-3);
    }
}

#[test]
fn x_speed_grows_with_rpm_and_acceleration_with_its_square() {
    let s = setup("3", 2, Direction::Same);
    let (p1, p2) = (plan(&s, 100.0, 1e9, 1e12), plan(&s, 200.0, 1e9, 1e12));
    assert!((p2.peak_x_speed / p1.peak_x_speed - 2.0).abs() < 1e-6);
    assert!((p2.peak_x_accel / p1.peak_x_accel - 4.0).abs() < 1e-6);
    assert!(p1.x_travel > 0.0);
}

#[test]
fn the_limiting_axis_is_named_and_the_speed_it_allows_fits() {
    let s = setup("3", 2, Direction::Same);
    let free = plan(&s, 300.0, 1e9, 1e12);
    let tight = plan(&s, 300.0, 1e9, free.peak_x_accel / 10.0);
    assert_eq!(tight.limited_by, Some(Limit::Accel));
    let ok_rpm = tight.max_rpm.unwrap();
    assert!(ok_rpm < 300.0 / 3.0 && ok_rpm > 300.0 / 3.3);
    assert_eq!(plan(&s, ok_rpm * 0.999, 1e9, free.peak_x_accel / 10.0).limited_by, None);
}

#[test]
fn with_both_limits_passed_the_tighter_one_is_named() {
    let s = setup("3", 2, Direction::Same);
    let free = plan(&s, 300.0, 1e9, 1e12);
    // speed passed by 2 x (it allows 150 rpm), acceleration by 100 x (30 rpm)
    let (v, a) = (free.peak_x_speed / 2.0, free.peak_x_accel / 100.0);
    let p = plan(&s, 300.0, v, a);
    assert_eq!(p.limited_by, Some(Limit::Accel));
    assert!((p.max_rpm.unwrap() - 30.0).abs() < 1e-6, "{:?}", p.max_rpm);
    // and the other way round: speed by 10 x (30 rpm), acceleration by 4 x (150 rpm)
    let p = plan(&s, 300.0, free.peak_x_speed / 10.0, free.peak_x_accel / 4.0);
    assert_eq!(p.limited_by, Some(Limit::Speed));
    assert!((p.max_rpm.unwrap() - 30.0).abs() < 1e-6, "{:?}", p.max_rpm);
}

#[test]
fn edges_that_cut_at_the_same_time_are_refused_as_overlap() {
    // Opposite sense, GR·R1 = R_c: the tip barely moves over the work at
    // contact (speed R_c − GR·R1, Ghionea eq. 5), so each pass dwells
    // past the next one's start.
    let s = Setup { cutter_radius_mm: 4.0, ..setup("2", 3, Direction::Opposite) };
    assert_eq!(plan(&s, 60.0, 1e9, 1e12).limited_by, Some(Limit::Overlap));
}
