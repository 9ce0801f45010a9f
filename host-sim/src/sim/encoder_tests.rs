use super::*;

#[test]
fn an_ideal_disc_counts_the_nearest_count() {
    let mut e = Encoder::new(2400);
    for i in -5000..5000 {
        let u = i as f64 * 0.0137 + 0.001;
        let angle = u / 2400.0 * TAU;
        assert_eq!(e.count(angle, 0), u.round() as i64, "u {u}");
    }
}

#[test]
fn a_rise_is_latched_with_the_count_after_it_and_its_microsecond() {
    let mut e = Encoder::new(2400);
    let per_count = TAU / 2400.0;
    // up from 0.3 to 1.3 counts over 40 µs: A rises at 0.5, 8 µs in
    e.follow(0.3 * per_count, 1.3 * per_count, 1.0, 40e-6);
    let r = e.edge_regs().unwrap();
    assert_eq!(r.count, 1);
    assert_eq!(r.stamp, (STAMP_ORIGIN + 1e6 - 32.0) as i64 as u16);
    // down from 3.0 to 2.0: A rises (on its way down) at 2.5, the count 2 after
    e.follow(3.0 * per_count, 2.0 * per_count, 2.0, 40e-6);
    assert_eq!(e.edge_regs().unwrap().count, 2);
    // no rise between 1.0 and 1.4: the last one stays
    e.follow(1.0 * per_count, 1.4 * per_count, 3.0, 40e-6);
    assert_eq!(e.edge_regs().unwrap().count, 2);
}

#[test]
fn quadrature_and_duty_errors_move_only_their_own_edges() {
    let mut e = Encoder::new(2400);
    e.disc = Disc { quadrature_counts: 0.12, duty_counts: -0.1, ..Disc::default() };
    let at = |e: &mut Encoder, u: f64| e.count(u / 2400.0 * TAU, 0);
    assert_eq!(at(&mut e, 0.49), 0);
    assert_eq!(at(&mut e, 0.51), 1); // A's rise stays
    assert_eq!(at(&mut e, 1.6), 1); // B's rise moved to 1.62
    assert_eq!(at(&mut e, 1.63), 2);
    assert_eq!(at(&mut e, 2.41), 3); // A's fall moved to 2.4
}

/// Every count begins at its `boundary_up`, on a true disc and a skewed one.
#[test]
fn each_count_begins_at_its_boundary() {
    for disc in [Disc::default(), Disc { quadrature_counts: 0.12, duty_counts: -0.1, ..Disc::default() }] {
        let e = Encoder::with_disc(2400, disc);
        for n in -9i64..20 {
            let b = e.boundary_up(n);
            // (to within rounding: count_at subtracts what this adds)
            assert_eq!(e.count_at(b + 1e-9), n, "{disc:?} {n} at {b}");
            assert_eq!(e.count_at(b - 1e-9), n - 1, "{disc:?} {n} below {b}");
        }
    }
}
