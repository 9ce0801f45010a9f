//! The BLDC drive's command (`polyturn_firmware::bldcout`): its TIM10 set-up
//! applied verbatim to the model of a general-purpose timer (RM0383 §14:
//! TIM10, one channel), and the pin's waveform measured: the frame, the
//! pulse each command makes, the stop taking effect in the frame under way.
//! The model compares CNT with the CCR1 in force at every count, as the
//! manual's PWM mode says ("CNT and CCRx are always compared"); its note
//! that PWM without the preload is guaranteed only in one-pulse mode
//! (§14.5.5 OC1PE) leaves the stop's "at once" to the bench procedure
//! (docs/src/bench.md, "The BLDC drive", step 6): these tests show the
//! words are right on that reading, not that silicon follows it. Where the
//! manual is silent (what clearing OC1PE does to a waiting value) the
//! tests run under both readings (`PreloadClear`).

mod tim10;

use polyturn_firmware::bldcout::{off, run_ops, stop_ops, Out};
use polyturn_firmware::regs::apply;
use tim10::{out, Tim10, MAX, READINGS};

#[test]
fn each_interface_makes_its_frame_and_its_stop_pulse() {
    // (name, pwm-hz, frame in cycles, stop's high time in cycles)
    let cases = [
        ("esc50", "1000", 1_920_000, 96_000),
        ("esc400", "1000", 240_000, 96_000),
        ("oneshot125", "1000", 48_000, 12_000),
        ("pwm", "1000", 96_000, 0),
        ("pwm", "20000", 4_800, 0),
    ];
    // (each under both readings of clearing OC1PE: the set-up clears it)
    for ((name, hz, frame, stop), r) in cases.into_iter().flat_map(|c| READINGS.map(|r| (c, r))) {
        let o = out(name, hz);
        let mut b = Tim10::set_up(&o, r);
        let step = if o.psc < 2 { 2 } else { 96 }; // a CK_CNT count or finer
        assert!((1..frame / step).all(|_| !b.after(step)), "{name} {hz}: low through the first frame");
        b.after(step); // its end, the first update
        let (high, _) = b.measure(step, frame);
        assert_eq!(high, stop, "{name} {hz}: the stop");
        // half speed: the pulse half way between stop and full
        let mut b2 = Tim10::set_up(&o, r);
        b2.t.write(off::CCR1, o.ccr(MAX as u32 / 2), u32::MAX);
        b2.after(frame); // preloaded: in force from the first update
        let (high, rise) = b2.measure(step, frame);
        let full = if stop == 0 { frame } else { 2 * stop };
        assert_eq!(high, (stop + full) / 2, "{name} {hz}: half speed");
        assert_eq!(rise, frame, "{name} {hz}: a pulse each frame");
    }
}

#[test]
fn full_speed_on_a_pwm_is_high_throughout() {
    for r in READINGS {
        let o = out("pwm", "5000");
        let mut b = Tim10::set_up(&o, r);
        b.t.write(off::CCR1, o.ccr(MAX as u32), u32::MAX);
        b.after(96_000_000 / 5_000); // preloaded: in force from the first update
        assert!((0..1_000).all(|_| b.after(97)), "{r:?}: CCR1 = ARR + 1: OC1REF held high (§14.3.9)");
    }
}

/// The tick's command: the words `app::bldc::command` applies, preloaded.
fn run(b: &mut Tim10, ccr: u32) {
    apply(&run_ops(ccr), b).unwrap();
}

/// The stop: the words `app::bldc::stop` applies.
fn stop(b: &mut Tim10, o: &Out) {
    apply(&stop_ops(o.stop), b).unwrap();
}

#[test]
fn the_stop_cuts_the_pulse_under_way() {
    // esc50 at full speed (2 000 µs); 1 500 µs into the pulse the stop is
    // written: the pin falls at once, not 18.5 ms later (under either
    // reading: without the stop's third word, the one written with the
    // preload off, `Stays` keeps the full pulse)
    for r in READINGS {
        let o = out("esc50", "1000");
        let mut b = Tim10::set_up(&o, r);
        run(&mut b, o.ccr(MAX as u32));
        b.after(20_000 * 96); // the preloaded command takes effect at the update
        assert!(b.after(1_500 * 96));
        stop(&mut b, &o);
        assert!(!b.after(96), "{r:?}: low within a µs of the stop");
        // and the next frame is the stop pulse, 1 000 µs
        b.after(18_500 * 96 - 96);
        let (high, _) = b.measure(96, 1_920_000);
        assert_eq!(high, 96_000, "{r:?}");
    }
}

#[test]
fn a_command_raised_after_the_pulse_fell_waits_for_the_next_frame() {
    // OneShot125 at half speed (187.5 µs); 200 µs into the frame, after
    // the fall, the tick raises it to full: preloaded, no second pulse in
    // this frame, 250 µs in the next (without the preload CNT < CCR1 would
    // hold again from 200 µs: a 50 µs runt after the real pulse)
    for r in READINGS {
        let o = out("oneshot125", "1000");
        let mut b = Tim10::set_up(&o, r);
        run(&mut b, o.ccr(MAX as u32 / 2));
        b.after(48_000); // to the update: the half-speed command is in
        assert!(b.after(96 * 100), "{r:?}: 100 µs in: high");
        assert!(!b.after(96 * 100), "{r:?}: 200 µs in: fallen at 187.5 µs");
        run(&mut b, o.ccr(MAX as u32));
        assert!((0..290).all(|_| !b.after(96)), "{r:?}: no runt before the frame ends");
        let (high, _) = b.measure(2, 48_000);
        assert_eq!(high, 24_000, "{r:?}: 250 µs from the next frame");
    }
}

#[test]
fn setting_up_again_in_a_pulse_never_stretches_it() {
    // esc400 in its stop pulse, 900 µs in; set up again (a new interface),
    // a µs between words: the pin falls by the third word (CCR1 = 0 with
    // the preload off) and stays low for the whole of the new interface's
    // first frame, so an ESC sees the cut pulse and the first stop pulse
    // apart, never 900 + 1 000 µs read as throttle. (The stop written with
    // the preload off after the counter started would let the pin rise
    // again a few µs after it fell.)
    for (next, frame) in [("esc50", 1_920_000), ("pwm", 96_000), ("oneshot125", 48_000)] {
        for r in READINGS {
            let o = out("esc400", "1000");
            let mut b = Tim10::set_up(&o, r);
            b.after(2_500 * 96); // the set-up's first frame, low
            assert!(b.after(900 * 96));
            let new = out(next, "1000");
            let fell = b.now + 3 * 96;
            b.word_by_word(&new.program(), 96, |i, b| assert!(i < 2 || !b.pin(), "{next} {r:?}: high after word {i}"));
            let low = b.now + b.low_for() - fell;
            assert!(low >= frame, "{next} {r:?}: low for {low} cycles, a frame is {frame}");
            assert!(b.high_for() <= new.stop as u64 * (new.psc as u64 + 1), "{next} {r:?}: the first pulse");
        }
    }
}

#[test]
fn the_stop_wins_over_a_command_waiting_in_the_preload() {
    // esc400 at full speed, a new (half) command preloaded for the next
    // frame; the stop comes 1 500 µs in: the pin falls at once, and the
    // next frame is the stop, not the waiting command
    for r in READINGS {
        let o = out("esc400", "1000");
        let mut b = Tim10::set_up(&o, r);
        run(&mut b, o.ccr(MAX as u32));
        b.after(2_500 * 96);
        run(&mut b, o.ccr(MAX as u32 / 2));
        assert!(b.after(1_500 * 96));
        stop(&mut b, &o);
        assert!(!b.after(96), "{r:?}");
        b.after(1_000 * 96 - 96);
        let (high, _) = b.measure(96, 240_000);
        assert_eq!(high, 96_000, "{r:?}: the stop's 1 000 µs");
    }
}

#[test]
fn setting_up_again_while_running_never_stretches_a_pulse() {
    // pwm at 1 kHz, 90 % duty, preloaded; 500 µs in, set up as esc50 a µs
    // a word: the pin falls, stays low for esc50's first 20 ms frame, and
    // the first pulse after is the stop's 1 000 µs
    for r in READINGS {
        let o = out("pwm", "1000");
        let mut b = Tim10::set_up(&o, r);
        run(&mut b, o.ccr(MAX as u32 / 10 * 9));
        b.after(96_000);
        assert!(b.after(500 * 96));
        let fell = b.now + 3 * 96;
        b.word_by_word(&out("esc50", "1000").program(), 96, |i, b| assert!(i < 2 || !b.pin(), "{r:?}: word {i}"));
        assert!(b.now + b.low_for() - fell >= 1_920_000, "{r:?}: low for a frame");
        let first = b.high_for();
        assert!(first <= 96_000, "{r:?}: first pulse {first} cycles");
    }
}

#[test]
fn the_stop_never_lets_a_waiting_command_through_between_its_words() {
    // esc400 at half speed (1 500 µs), full speed waiting in the preload;
    // the stop comes 1 600 µs in, the pin already low. Word by word, under
    // either reading, the waiting 2 000 µs is never in force (where
    // clearing OC1PE puts a waiting value in force, clearing the preload
    // first would let the pin rise again for 400 µs), and
    // the stop ends waiting, the preload on again
    for r in READINGS {
        let o = out("esc400", "1000");
        let mut b = Tim10::set_up(&o, r);
        run(&mut b, o.ccr(MAX as u32 / 2));
        b.after(2_500 * 96);
        run(&mut b, o.ccr(MAX as u32));
        assert!(!b.after(1_600 * 96), "the half-speed pulse is over");
        b.word_by_word(&stop_ops(o.stop), 10, |i, b| {
            assert_ne!(b.t.active_ccr(0), o.ccr(MAX as u32), "{r:?}: the waiting command in force after word {i}");
            assert!(!b.pin(), "{r:?}: the pin high after word {i}");
        });
        assert_eq!((b.t.active_ccr(0), b.t.get(off::CCR1)), (0, o.stop), "{r:?}: 0 in force, the stop waiting");
        assert_eq!(b.t.get(off::CCMR1), polyturn_firmware::bldcout::CCMR1_LIVE, "{r:?}: the preload on again");
    }
}

#[test]
fn a_stop_never_raises_the_pin() {
    // a stop at any point of a frame leaves the pin low to the frame's end
    // (then the stop pulse): in the first frame after a set-up, where 0 is
    // in force (a stop written in force there would start a pulse mid-frame
    // just after the set-up's cut), and in a running frame before CNT
    // reaches the stop's width
    for r in READINGS {
        let o = out("esc400", "1000");
        for at_us in [1, 100, 900, 1_200, 2_400] {
            let mut b = Tim10::set_up(&o, r);
            b.after(at_us * 96);
            stop(&mut b, &o);
            let low = b.low_for();
            assert!(at_us * 96 + low >= 240_000 - 96, "{r:?}: first frame, stop at {at_us} µs: low {low}");
            assert_eq!(b.high_for(), 1_000 * 96 - 96, "{r:?}: then the stop pulse (to a µs)");
            // a running frame, the command at full speed
            run(&mut b, o.ccr(MAX as u32));
            b.after(2 * 240_000 - b.now % 240_000 + at_us * 96);
            let was = b.pin();
            stop(&mut b, &o);
            assert!(!b.after(1), "{r:?}: running, stop at {at_us} µs (pin was {was})");
            assert!(at_us * 96 + b.low_for() >= 240_000 - 96, "{r:?}: running, stop at {at_us} µs");
        }
    }
}
