//! The lost-step alarm (`set cutter-cpr`): an encoder on the stepper's
//! shaft against the steps sent. It must fire within a few milliseconds of
//! a jam in the cut, and never on a good cut, with the encoder's whole
//! counts and the motor's step-to-step error (±5 % of a step) modelled.

use polyturn_host::geometry::Direction;
use polyturn_host::sim::{Event, Scenario, Start};
use polyturn_scenarios::*;
use polyturn_sync::{DriveKind, Fault};

/// `sc` with an encoder of `cpr` counts on the shaft and ±5 % step error.
fn with_shaft_encoder(mut sc: Scenario, cpr: u32) -> Scenario {
    sc.core = sc.core.with("cutter-cpr", &cpr.to_string()).unwrap();
    sc.step_error = 0.05;
    sc
}

#[test]
fn a_jam_in_the_cut_trips_lost_steps_within_two_milliseconds() {
    for cpr in [1000, 4000] {
        // the hexagon, synced and cutting at 600 rpm (64 000 steps/s)
        let mut sc = with_shaft_encoder(scenario(hexagon(), 600.0, 20.0, 0.02, Start::Rest, DriveKind::Stepper), cpr);
        sc.events.push(Event::Jam(1.5));
        let r = simulate(&sc);
        let (tick, f) = *r.faults.first().unwrap_or_else(|| panic!("cpr {cpr}: no fault"));
        assert_eq!(f, Fault::LostSteps, "cpr {cpr}: {:?}", r.faults);
        let after_ms = (seconds(tick) - 1.5) * 1e3;
        // 32 steps at 64 000 steps/s is 0.5 ms, plus a count and a tick
        assert!((0.0..=2.0).contains(&after_ms), "cpr {cpr}: {after_ms:.2} ms after the jam");
        eprintln!("cpr {cpr}: lost-steps {after_ms:.2} ms after the jam");
    }
}

#[test]
fn without_a_shaft_encoder_a_jam_goes_unseen() {
    // what every peer does today: the pulses are counted at the MCU's pin
    let mut sc = scenario(hexagon(), 600.0, 20.0, 0.02, Start::Rest, DriveKind::Stepper);
    sc.events.push(Event::Jam(1.5));
    let r = simulate(&sc);
    assert!(!r.faults.iter().any(|f| f.1 == Fault::LostSteps), "{:?}", r.faults);
}

/// The cutting scenarios of `tests/cutting.rs`, 1 000 turns each.
fn cuts() -> Vec<(&'static str, f64, Scenario)> {
    let turns = 1000.0;
    vec![
        ("2:1 x 3, 600 rpm, 2 %", 600.0, scenario(hexagon(), 600.0, turns, 0.02, Start::Rest, DriveKind::Stepper)),
        (
            "11/3 x 3, 300 rpm, 5 %, spinning",
            300.0,
            scenario(setup("11/3", 3, Direction::Same, 2.0), 300.0, turns, 0.05, Start::Spinning, DriveKind::Stepper),
        ),
        (
            "7/2 x 2 opposite, 400 rpm, 2 %",
            400.0,
            scenario(setup("7/2", 2, Direction::Opposite, 2.0), 400.0, turns, 0.02, Start::Rest, DriveKind::Stepper),
        ),
        (
            "4/3 x 3, 900 rpm, spinning",
            900.0,
            scenario(setup("4/3", 3, Direction::Same, 2.0), 900.0, turns, 0.0, Start::Spinning, DriveKind::Stepper),
        ),
    ]
}

#[test]
fn no_false_alarm_over_a_thousand_turns_of_every_cut() {
    for (name, rpm, sc) in cuts() {
        for cpr in [1000, 4000] {
            let r = simulate(&with_shaft_encoder(sc.clone(), cpr));
            assert!(r.faults.is_empty(), "{name}, cpr {cpr}: {:?}", r.faults);
            // and with a margin: under half the default limit (32 steps)
            let worst = r.max_shaft_error_steps;
            assert!(worst > 0.0 && worst < 16.0, "{name}, cpr {cpr}: the shaft {worst:.2} steps from the books");
            eprintln!("{name}, cpr {cpr}: the shaft at most {worst:.2} steps from the steps sent");
            // the lathe's turns while synced: at least the thousand cut
            let turns = seconds(r.synced_ticks) * rpm / 60.0;
            assert!(turns >= 1000.0, "{name}: {turns:.0} turns synced");
        }
    }
}
