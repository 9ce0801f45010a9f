//! While synced at a steady speed the steps really made keep to the exact
//! gear, including the step output's two ticks of pipeline; a BLDC cutter
//! that does not follow its command stalls.

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;
use crate::gear::Scale;

#[test]
fn at_a_steady_speed_the_steps_made_are_the_exact_gear_at_each_windows_end() {
    for counts in [1.0, -2.0, 0.5] {
        let mut r = Rig::new(Config::default());
        r.run(per_tick(counts), 5_000);
        r.c.engage().unwrap();
        r.until(per_tick(counts), 100_000, |c| c.state() == State::Synced);
        r.run(per_tick(counts), 20_000);
        let scale = r.c.derived().scale;
        let mut worst = 0;
        for _ in 0..2_000 {
            r.tick(per_tick(counts));
            // the window that has just run ends when the next tick reads
            // the lathe: the gear's target then, plus the whole turns
            // dropped at engaging
            let end = (r.lathe_q16 + per_tick(counts)) >> 16;
            let exact = Scale::round(scale, end) + r.c.turn_offset_steps();
            worst = worst.max((r.cutter_net - exact).abs());
            // and the status says the cutter is on the gear
            let e = r.c.status().phase_error_q16;
            assert!(e.abs() < 1 << 14, "{counts} counts a tick: phase error {e}");
        }
        assert_eq!(r.c.fault(), None);
        // at whole counts a tick the count is the lathe's true angle; at
        // half a count the true angle runs up to half a count (1⅓ steps)
        // past the last count, and the interpolated target with it
        let tolerance = if counts == 0.5 { 1 } else { 0 };
        assert!(worst <= tolerance, "{counts} counts a tick: {worst} steps off");
    }
}

#[test]
fn a_bldc_cutter_whose_encoder_stands_still_stalls_after_a_fifth_of_a_second() {
    let mut c = Controller::new(Config { drive: DriveKind::Bldc, ..Config::default() }, Timing::FIRMWARE);
    c.start(0, 0, 0);
    // a slow turn; the encoder never counts
    c.jog(360_000).unwrap();
    // a fifth of a second, counted once the command is a sixteenth of
    // max-rate or more (the phase loop's error grows it to that)
    let fifth = Timing::FIRMWARE.tick_hz / 5;
    assert_eq!(c.derived().stall_ticks, fifth);
    let sixteenth = (c.derived().limits.max_velocity >> 4) as i32;
    let mut judged_from = None;
    for k in 1..40_000 {
        let out = c.tick(&TickInput::default());
        if out.speed_q16.abs() >= sixteenth {
            judged_from.get_or_insert(k);
        }
        if c.fault().is_some() {
            assert_eq!(c.fault(), Some(Fault::Stall));
            let from = judged_from.expect("a stall with the command under a sixteenth");
            assert_eq!(k - from, fifth, "after {k} ticks");
            assert!(out.enable && !out.halt, "a stall ramps down");
            return;
        }
    }
    panic!("no stall: {:?}", c.state());
}
