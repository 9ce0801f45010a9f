//! The tick's BLDC command against a stop that pre-empts it
//! (`polyturn_firmware::bldcout::Interlock`): the E-stop interrupt runs above
//! the tick and may land anywhere in the tick's command. Each write here
//! takes time on the model of TIM10 (RM0383 §14), and the frame's update
//! event is put at every point of the words in turn, under both readings
//! of clearing OC1PE: the stop must end in force and waiting, and the pin
//! must never carry the command after the stop for longer than the few
//! cycles between the command's word and the stop written again.

mod tim10;

use polyturn_firmware::bldcout::{off, Interlock, Out};
use polyturn_firmware::regs::Bus;
use polyturn_stm32_model::PreloadClear;
use tim10::{out, Tim10, MAX, READINGS};

/// Cycles a TIM10 write takes here (an APB2 write and the code around it).
const GAP: u64 = 16;
/// TIM10's cycles (96 MHz) a control tick.
const TICK_CYCLES: u64 = tim10::HZ / polyturn_firmware::board::TICK_HZ as u64;
/// Cycles from the E-stop's edge to its first TIM10 write: the exception
/// entry (12) and TIM1's stop before it.
const ENTRY: u64 = 20;

/// Where the stop lands relative to the tick's command.
#[derive(Clone, Copy, Debug)]
enum Lands {
    /// after the tick began, before its command
    Before,
    /// just before the command's word
    AtTheWord,
    /// just after the word, before the command looks again
    AfterTheWord,
}

/// A bus whose writer is pre-empted once by the E-stop's stop: before
/// write `at` (counting from 0), or after it with `after`.
struct Preempted<'a> {
    b: Tim10,
    interlock: &'a Interlock,
    at: usize,
    after: bool,
    writes: usize,
}

impl Preempted<'_> {
    fn new(b: Tim10, interlock: &Interlock, at: usize, after: bool) -> Preempted<'_> {
        Preempted { b, interlock, at, after, writes: 0 }
    }

    fn fire(&mut self) {
        self.b.pass(ENTRY);
        self.interlock.stop(&mut self.b);
    }
}

impl Bus for Preempted<'_> {
    fn write(&mut self, addr: u32, value: u32) {
        let here = self.writes == self.at;
        self.writes += 1;
        if here && !self.after {
            self.fire();
        }
        self.b.write(addr, value);
        if here && self.after {
            self.fire();
        }
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.b.read(addr)
    }
    fn delay(&mut self, _: u32) {}
}

/// Cycles from one frame's start to the next.
fn frame(o: &Out) -> u64 {
    (o.arr as u64 + 1) * (o.psc as u64 + 1)
}

/// `o` running at half speed, then at `offset` cycles before a frame's
/// update the tick's command to full speed with a stop landing as
/// `lands`: the pin's high cycles from there to the end of the frame that
/// update begins (the words' own time included), the cycles of them with
/// the command in force, and (CCR1 in force, CCR1 waiting) then.
fn race(o: &Out, r: polyturn_stm32_model::PreloadClear, lands: Lands, offset: u64) -> (u64, u64, (u32, u32)) {
    let interlock = Interlock::new();
    let mut b = Tim10::set_up(o, r);
    interlock.set_up(o, &mut b);
    let f = frame(o);
    interlock.command(o.ccr(MAX as u32 / 2), interlock.stops(), &mut b);
    b.after(2 * f - offset - b.now % f);
    b.gap = GAP;
    assert!(!b.pin(), "the half-speed pulse is over ({offset} before the update)");
    let update = b.now + offset;
    b.watch = Some(o.ccr(MAX as u32));
    let since = interlock.stops();
    if let Lands::Before = lands {
        interlock.stop(&mut b);
    }
    let mut p = Preempted::new(
        b,
        &interlock,
        if let Lands::Before = lands { usize::MAX } else { 0 },
        matches!(lands, Lands::AfterTheWord),
    );
    interlock.command(o.ccr(MAX as u32), since, &mut p);
    let mut b = p.b;
    // to the end of the frame the update began
    let end = update + f;
    // (after the words only 0 or the stop can be in force: sampled)
    let after = (b.now..end).step_by(2).filter(|_| b.after(2)).count() as u64 * 2;
    (b.high_in_gaps + after, b.watched_high, (b.t.active_ccr(0), b.t.get(off::CCR1)))
}

#[test]
fn a_stop_anywhere_in_the_ticks_command_is_the_last_word() {
    for (name, hz) in [("pwm", "20000"), ("oneshot125", "1000"), ("esc400", "1000")] {
        let o = out(name, hz);
        let stop_cycles = o.stop as u64 * (o.psc as u64 + 1);
        for r in READINGS {
            for lands in [Lands::Before, Lands::AtTheWord, Lands::AfterTheWord] {
                // the update at every point from before the first word to
                // after the last (a stop, the word, the stop again: 11
                // writes and the interrupt's entry)
                for offset in (1..12 * GAP + ENTRY).step_by(2) {
                    let (high, command, ccr) = race(&o, r, lands, offset);
                    let what = format!("{name} {r:?} {lands:?}, the update {offset} cycles on");
                    assert_eq!(ccr, (o.stop, o.stop), "{what}: the stop in force and waiting");
                    // no more of the command than the cycles from the word
                    // to the stop's third (the interrupt's entry, three
                    // writes); none if the stop came first; and no more
                    // high than that and that frame's stop pulse
                    let runt = if let Lands::Before = lands { 0 } else { ENTRY + 3 * GAP };
                    assert!(command <= runt, "{what}: the command in force {command} cycles");
                    assert!(high <= stop_cycles + runt + 2, "{what}: high {high} cycles");
                }
            }
        }
    }
}

/// esc400 set up, its interlock and the pin, a frame run at full speed: at the
/// next update, the full-speed pulse starting.
fn running_full(o: &Out, r: PreloadClear) -> (Interlock, Tim10) {
    let interlock = Interlock::new();
    let mut b = Tim10::set_up(o, r);
    interlock.set_up(o, &mut b);
    interlock.command(o.ccr(MAX as u32), interlock.stops(), &mut b);
    b.after(frame(o));
    (interlock, b)
}

#[test]
fn a_speed_falling_to_the_stop_keeps_the_pulse_under_way() {
    // full speed (2 000 µs) under way, 500 µs in; the tick's command falls
    // to the stop (the phase loop asking to slow past zero, or disengaged):
    // no fault, so the pulse runs to its end (cut, an ESC would read a
    // pulse below its range), and the next frame is the stop's
    for r in READINGS {
        let o = out("esc400", "1000");
        let (interlock, mut b) = running_full(&o, r);
        assert!(b.after(500 * 96));
        interlock.command(o.stop, interlock.stops(), &mut b);
        let high = 500 * 96 + b.high_for();
        assert!(high.abs_diff(2 * 96_000) <= 96, "{r:?}: 2 000 µs (to a µs): {high}");
        b.after(frame(&o) - high - 96);
        let stop = b.high_for();
        assert!(stop.abs_diff(96_000) <= 96, "{r:?}: then the stop's 1 000 µs: {stop}");
    }
}

#[test]
fn a_halt_cuts_the_pulse_at_once() {
    for r in READINGS {
        let o = out("esc400", "1000");
        let (interlock, mut b) = running_full(&o, r);
        assert!(b.after(1_500 * 96));
        interlock.halt(&mut b);
        assert!(!b.after(1), "{r:?}: low at once");
        assert_eq!((b.t.active_ccr(0), b.t.get(off::CCR1)), (0, o.stop), "{r:?}: cut, the stop waiting");
    }
}

#[test]
fn idle_ticks_leave_the_stop_pulses_whole() {
    // after a halt, ticks commanding the stop, and halting
    // again, write nothing: every frame's stop pulse is a whole 1 000 µs
    // (writing the stop each tick would cut each one short)
    for r in READINGS {
        let o = out("esc400", "1000");
        let (interlock, mut b) = running_full(&o, r);
        interlock.halt(&mut b);
        b.after(frame(&o) - b.now % frame(&o)); // the next frame
        let mut highs = 0;
        for tick in 0..(3 * frame(&o) / TICK_CYCLES) {
            if tick % 2 == 0 {
                interlock.command(o.stop, interlock.stops(), &mut b);
            } else {
                interlock.halt(&mut b);
            }
            highs += (0..TICK_CYCLES / 96).filter(|_| b.after(96)).count();
        }
        assert!((2_997..=3_000).contains(&highs), "{r:?}: three whole stop pulses (to a µs each): {highs} µs");
    }
}

#[test]
fn a_stop_anywhere_in_a_set_up_leaves_the_new_stop_waiting_and_no_long_pulse() {
    // esc400 at full speed, 600 µs into its pulse; set up as esc50 (20 ms
    // frame, 1 000 µs stop) with the E-stop landing before or after each
    // of the set-up's words: the pin falls by the set-up's third word and
    // stays low a whole new frame, then gives the new stop's pulse, and the
    // new stop is what waits (a stop after the last word, before the interlock
    // kept the new stop, left 0: no pulse at all, an ESC's signal lost)
    let (old, new) = (out("esc400", "1000"), out("esc50", "1000"));
    let words = new.program().len();
    for r in READINGS {
        for at in 0..words {
            for after in [false, true] {
                let interlock = Interlock::new();
                let mut b = Tim10::set_up(&old, r);
                interlock.set_up(&old, &mut b);
                interlock.command(old.ccr(MAX as u32), interlock.stops(), &mut b);
                b.after(2 * 240_000 + 600 * 96);
                b.gap = GAP;
                let mut p = Preempted::new(b, &interlock, at, after);
                interlock.set_up(&new, &mut p);
                let mut b = p.b;
                let what = format!("{r:?}, the stop {} word {at}", if after { "after" } else { "before" });
                let fell = b.last_high_at;
                let low = b.now + b.low_for() - fell;
                assert!(low >= 1_920_000 - 96, "{what}: low {low} cycles, a frame is 1 920 000");
                let pulse = b.high_for();
                assert!(pulse.abs_diff(96_000) <= 96, "{what}: the stop's 1 000 µs, got {pulse} cycles");
                assert_eq!(b.t.get(off::CCR1), new.stop, "{what}: the stop waiting");
                assert!(fell < 600 * 96 + 2 * 240_000 + 3 * GAP + ENTRY + 5 * GAP, "{what}: fell at {fell}");
            }
        }
    }
}

#[test]
fn an_estop_inside_the_ticks_own_stop_leaves_the_stop_waiting() {
    // the tick halts a drive running at full speed (an immediate fault),
    // and the E-stop lands before or after each of that stop's words:
    // the pin is low once both are done, stays low to the frame's end,
    // and the stop waits, whichever reading of clearing OC1PE
    let o = out("esc400", "1000");
    for r in READINGS {
        for at in 0..5 {
            for after in [false, true] {
                let interlock = Interlock::new();
                let mut b = Tim10::set_up(&o, r);
                interlock.set_up(&o, &mut b);
                interlock.command(o.ccr(MAX as u32), interlock.stops(), &mut b);
                b.after(frame(&o) + 1_500 * 96);
                b.gap = GAP;
                let mut p = Preempted::new(b, &interlock, at, after);
                interlock.halt(&mut p);
                let mut b = p.b;
                let what = format!("{r:?}, the E-stop {} word {at}", if after { "after" } else { "before" });
                assert_eq!((b.t.active_ccr(0), b.t.get(off::CCR1)), (0, o.stop), "{what}: cut, the stop waiting");
                let to_end = frame(&o) - b.now % frame(&o);
                assert!(b.low_for() + 96 >= to_end, "{what}: low to the frame's end");
            }
        }
    }
}
