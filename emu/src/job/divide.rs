//! Dividing on the real image: `divide 6` on the console, and the chuck
//! turned by hand (the host simulator's spindle, slowly, both ways) to
//! each division in turn, past the index, and across a reset (the NRST
//! button: the spindle stays where it is, the board's count starts again).
//! At each rest the image's readout must be the truth's: the spindle's
//! count from the index (A/B and the index on PA6/PA7/PB0, the index at
//! each whole turn of the count) worked out by `polyturn_sync::angle`,
//! and on the division asked for, within a count. After the reset, before
//! the index, the angle is from the start; past the index, the divisions
//! are where they were.

use super::lathe::LatheDrive;
use super::{ESTOP, GPIOB, SYSCLK};
use crate::checks::Report;
use crate::image::Image;
use crate::machine::{Machine, Reset};
use crate::usb::scenario::{enumerate_on, exchange};
use polyturn_host::sim::lathe::{LatheProfile, Leg};
use polyturn_stm32_model::Params;
use polyturn_sync::angle::{Angle, Division};
use std::rc::Rc;

/// The default settings' encoder, and the divisions asked for.
const CPR: i64 = 2400;
const DIVISIONS: u32 = 6;
/// A hand's flick of the chuck: up to 60 rpm, reached in an eighth of a
/// second (a slower hand changes nothing the job checks, and costs time).
const HAND_RPM: f64 = 60.0;
const HAND_ACCEL: f64 = 480.0;
/// The rest at each division (the readout is read half-way), and the
/// longer one the reset and the enumeration after it take.
const REST_S: f64 = 0.3;
const RESET_REST_S: f64 = 1.5;

/// The moves, in divisions (signed: the way the count goes up), and
/// whether the board is reset at the rest after the move.
/// Forward past the index, on, back; a reset; back past the index (the
/// first pass after the reset the other way), and on to where it was.
const MOVES: [(i64, bool); 5] = [(7, false), (1, false), (-1, true), (-2, false), (3, false)];

/// A move of `divisions` sixths of a turn: up to the hand's speed, a hold,
/// down to rest, then the rest.
fn legs(divisions: i64, rest_s: f64) -> [Leg; 2] {
    let (v, a) = (HAND_RPM / 60.0, HAND_ACCEL / 60.0); // rev/s, rev/s²
    let turns = divisions.abs() as f64 / DIVISIONS as f64;
    // the two ramps turn v²/a; the hold the rest at v
    let hold_s = (turns - v * v / a) / v;
    let rpm = HAND_RPM * divisions.signum() as f64;
    [Leg { rpm, accel_rpm_per_s: HAND_ACCEL, hold_s }, Leg { rpm: 0.0, accel_rpm_per_s: HAND_ACCEL, hold_s: rest_s }]
}

/// The whole profile, and the lathe time (s) half-way through each rest.
fn profile() -> (LatheProfile, Vec<f64>) {
    let (mut legs_all, mut reads, mut t) = (Vec::new(), Vec::new(), 0.0);
    let ramp_s = HAND_RPM / HAND_ACCEL;
    for &(n, reset) in &MOVES {
        let rest_s = if reset { RESET_REST_S } else { REST_S };
        let l = legs(n, rest_s);
        t += 2.0 * ramp_s + l[0].hold_s;
        reads.push(t + if reset { 0.05 } else { rest_s / 2.0 });
        t += rest_s;
        legs_all.extend(l);
    }
    let p = LatheProfile { start_rpm: 0.0, legs: legs_all, ripple: 0.0, wander: 0.0, dips: vec![] };
    (p, reads)
}

/// The readout the truth gives: the spindle's count `counts` from the
/// origin the board should have.
fn truth(counts: i64, from_index: bool) -> String {
    let a = Angle::of(counts, None, CPR as u32);
    let a = Angle { from_index, ..a };
    let d = Division::of(&a, DIVISIONS);
    let from = if from_index { "index" } else { "start" };
    format!(
        "ok divide={DIVISIONS} division={} division_deg={} to_deg={} to_counts={} within={} angle_deg={} angle_from={from}",
        d.number,
        d.at_degrees(),
        d.to_degrees(),
        d.to_counts(),
        if d.within() { "yes" } else { "no" },
        a.degrees()
    )
}

fn booted(m: Machine) -> Result<Machine, String> {
    let mut m = m;
    m.drive(GPIOB, ESTOP, Some(false));
    Ok(enumerate_on(m)?.0)
}

/// Whether the spindle turned from count `from` to `to` enters a whole
/// turn's count, where the index is.
fn crosses_index(from: i64, to: i64) -> bool {
    let (lo, hi) = if to > from { (from + 1, to) } else { (to, from - 1) };
    lo <= hi && hi.div_euclid(CPR) > (lo - 1).div_euclid(CPR)
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let mut m = booted(Machine::new(image.clone(), Params::default(), &[])?)?;
    let started = exchange(&mut m, "divide 6\n")?.0;
    let (p, reads) = profile();
    // the lathe's time 0, in this machine's cycles (before 0 after a reset)
    let mut t0 = m.chip().now as i64;
    m.cpr = CPR as u32;
    m.lathe = Some(LatheDrive::motor(p, 1, CPR as u32, t0 as u64, SYSCLK));
    let mut ok = started == truth(0, false);
    let mut seen = vec![format!("at the start: {started:?}")];
    // where the hand stops, whether the board has seen the index since it
    // started, and the count it started at
    let (mut pos, mut indexed, mut start, mut total) = (0i64, false, 0i64, 0u64);
    for (&(n, reset), &t) in MOVES.iter().zip(&reads) {
        let next = pos + n * CPR / DIVISIONS as i64;
        indexed |= crosses_index(pos, next);
        pos = next;
        let at = (t0 + (t * SYSCLK as f64) as i64).max(0) as u64;
        let now = m.chip().now;
        m.run(at.saturating_sub(now));
        let count = m.lathe.as_ref().map_or(0, |l| l.count);
        let got = exchange(&mut m, "divide\n")?.0;
        let want = if indexed { truth(count, true) } else { truth(count - start, false) };
        ok &= got == want && count == pos && got.contains(" within=yes ");
        let wrong = if got == want { String::new() } else { format!(" (want {want:?})") };
        seen.push(format!("count {count} ({n:+}): {got:?}{wrong}"));
        if reset {
            let now = m.chip().now;
            total += now;
            m = booted(m.reset_as(&Reset::Pin)?)?;
            t0 -= now as i64;
            (indexed, start) = (false, count);
            let again = exchange(&mut m, "divide 6\n")?.0;
            ok &= again == truth(0, false);
            seen.push(format!("reset, then: {again:?}"));
        }
    }
    r.line(ok, "divide", &seen.join("; "));
    Ok(total + m.chip().now)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hands_moves_end_on_the_divisions_and_the_truth_reads_them() {
        let (p, reads) = profile();
        assert_eq!(p.legs.len(), 2 * MOVES.len());
        assert!(p.legs.iter().all(|l| l.hold_s > 0.0), "each move long enough for its ramps");
        // the lathe model turned through the profile stops on each division
        let mut lathe = polyturn_host::sim::lathe::Lathe::new(p, 1);
        let (mut t, mut target) = (0.0, 0i64);
        let tick_s = 1.0 / f64::from(polyturn_firmware::board::TICK_HZ);
        for (&(n, _), &read) in MOVES.iter().zip(&reads) {
            while t < read {
                lathe.advance(tick_s);
                t += tick_s;
            }
            target += n * CPR / DIVISIONS as i64;
            let counts = lathe.angle / std::f64::consts::TAU * CPR as f64;
            assert!((counts - target as f64).abs() < 0.25, "{counts} for {target}");
        }
        assert_eq!(
            truth(2800, true),
            "ok divide=6 division=1 division_deg=60.0 to_deg=0.0 to_counts=0.00 within=yes angle_deg=60.0 angle_from=index"
        );
        assert!(truth(-400, false).ends_with(
            " division=5 division_deg=300.0 to_deg=0.0 to_counts=0.00 within=yes angle_deg=300.0 angle_from=start"
        ));
        assert!(crosses_index(0, 2800) && crosses_index(2401, 2400) && crosses_index(2000, 2800));
        assert!(!crosses_index(2400, 2000) && !crosses_index(2800, 3200) && !crosses_index(0, -400));
    }
}
