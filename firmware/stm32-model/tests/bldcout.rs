//! The BLDC drive's command (`polyturn_firmware::bldcout`): its TIM10 set-up
//! applied verbatim to the model of a general-purpose timer (RM0383 §14:
//! TIM10, one channel), and the pin's waveform measured: the frame, the
//! pulse each command makes, the stop taking effect in the frame under way.
//! The model compares CNT with the CCR1 in force at every count, as the
//! manual's PWM mode says ("CNT and CCRx are always compared"); its note
//! that PWM without the preload is guaranteed only in one-pulse mode
//! (§14.5.5 OC1PE) leaves the stop's "at once" to the bench procedure
//! (docs/src/bench.md, "The BLDC drive", step 6): these tests show the
//! words are right on that reading, not that silicon follows it.

use polyturn_firmware::bldcout::{off, run_ops, stop_ops, Out, TIM10};
use polyturn_firmware::regs::{apply, Bus};
use polyturn_stm32_model::chip::gptimer::GpTimer;
use polyturn_sync::Config;

const HZ: u64 = 96_000_000;
const MAX: i64 = 524_288;

struct Tim10 {
    t: GpTimer,
    now: u64,
}

impl Bus for Tim10 {
    fn write(&mut self, addr: u32, value: u32) {
        self.t.write(addr - TIM10, value, u32::MAX);
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.t.read(addr - TIM10)
    }
    fn delay(&mut self, _: u32) {}
}

impl Tim10 {
    fn set_up(o: &Out) -> Tim10 {
        let mut b = Tim10 { t: GpTimer::new(16, 1), now: 0 };
        apply(&o.program(), &mut b).unwrap();
        b
    }

    /// The pin's level, `cycles` CPU cycles on.
    fn after(&mut self, cycles: u64) -> bool {
        self.now += cycles;
        self.t.advance(self.now, HZ, HZ);
        self.t.oc_out(0).expect("CC1E on: the pin is driven")
    }

    /// How long the pin stays high from now, cycles (µs steps, at most a
    /// 25 ms look).
    fn high_for(&mut self) -> u64 {
        (0..25_000).take_while(|_| self.after(96)).count() as u64 * 96
    }

    /// From a frame's start: (high cycles, frame cycles), sampled every
    /// `step` cycles over two frames.
    fn measure(&mut self, step: u64, frame: u64) -> (u64, u64) {
        let samples: Vec<bool> = (0..2 * frame / step).map(|_| self.after(step)).collect();
        let first = &samples[..(frame / step) as usize];
        let high = first.iter().filter(|&&h| h).count() as u64 * step;
        // the next frame's pulse begins where the first ends (sample k is
        // at (k + 1) × step)
        let rise = samples.windows(2).position(|w| !w[0] && w[1]).map(|i| (i as u64 + 2) * step);
        (high, rise.unwrap_or(0))
    }
}

fn out(name: &str, hz: &str) -> Out {
    let c = Config::default().with("bldc-out", name).unwrap().with("pwm-hz", hz).unwrap();
    Out::new(&c, MAX)
}

#[test]
fn each_interface_makes_its_frame_and_its_stop_pulse() {
    // (name, pwm-hz, frame in cycles, stop's high time in cycles)
    for (name, hz, frame, stop) in [
        ("esc50", "1000", 1_920_000, 96_000),
        ("esc400", "1000", 240_000, 96_000),
        ("oneshot125", "1000", 48_000, 12_000),
        ("pwm", "1000", 96_000, 0),
        ("pwm", "20000", 4_800, 0),
    ] {
        let o = out(name, hz);
        let mut b = Tim10::set_up(&o);
        let step = if o.psc < 2 { 2 } else { 96 }; // a CK_CNT count or finer
        let (high, _) = b.measure(step, frame);
        assert_eq!(high, stop, "{name} {hz}: the stop");
        // half speed: the pulse half way between stop and full
        let mut b2 = Tim10::set_up(&o);
        b2.t.write(off::CCR1, o.ccr(MAX as u32 / 2), u32::MAX);
        let (high, rise) = b2.measure(step, frame);
        let full = if stop == 0 { frame } else { 2 * stop };
        assert_eq!(high, (stop + full) / 2, "{name} {hz}: half speed");
        assert_eq!(rise, frame, "{name} {hz}: a pulse each frame");
    }
}

#[test]
fn full_speed_on_a_pwm_is_high_throughout() {
    let o = out("pwm", "5000");
    let mut b = Tim10::set_up(&o);
    b.t.write(off::CCR1, o.ccr(MAX as u32), u32::MAX);
    assert!((0..1_000).all(|_| b.after(97)), "CCR1 = ARR + 1: OC1REF held high (§14.3.9)");
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
    // written: the pin falls at once, not 18.5 ms later
    let o = out("esc50", "1000");
    let mut b = Tim10::set_up(&o);
    run(&mut b, o.ccr(MAX as u32));
    b.after(20_000 * 96); // the preloaded command takes effect at the update
    assert!(b.after(1_500 * 96));
    stop(&mut b, &o);
    assert!(!b.after(96), "low within a µs of the stop");
    // and the next frame is the stop pulse, 1 000 µs
    b.after(18_500 * 96 - 96);
    let (high, _) = b.measure(96, 1_920_000);
    assert_eq!(high, 96_000);
}

#[test]
fn a_command_raised_after_the_pulse_fell_waits_for_the_next_frame() {
    // OneShot125 at half speed (187.5 µs); 200 µs into the frame, after
    // the fall, the tick raises it to full: preloaded, no second pulse in
    // this frame, 250 µs in the next (without the preload CNT < CCR1 would
    // hold again from 200 µs: a 50 µs runt after the real pulse)
    let o = out("oneshot125", "1000");
    let mut b = Tim10::set_up(&o);
    run(&mut b, o.ccr(MAX as u32 / 2));
    b.after(48_000); // to the update: the half-speed command is in
    assert!(b.after(96 * 100), "100 µs in: high");
    assert!(!b.after(96 * 100), "200 µs in: fallen at 187.5 µs");
    run(&mut b, o.ccr(MAX as u32));
    assert!((0..290).all(|_| !b.after(96)), "no runt before the frame ends");
    let (high, _) = b.measure(2, 48_000);
    assert_eq!(high, 24_000, "250 µs from the next frame");
}

#[test]
fn setting_up_again_in_a_pulse_never_stretches_it() {
    // esc400 in its stop pulse, 900 µs in; set up again (a new interface):
    // CCR1 = 0 first drops the pin at once, and the first pulse after is no
    // longer than the stop, never 900 + 1 000 µs read as throttle
    let o = out("esc400", "1000");
    let mut b = Tim10::set_up(&o);
    assert!(b.after(900 * 96));
    let program = out("esc50", "1000").program();
    for (i, op) in program.iter().enumerate() {
        if let polyturn_firmware::regs::Op::Write(a, v) = *op {
            b.write(a, v);
            // low from the second word (CCR1 = 0) to the last (the stop)
            let between = (1..program.len() - 1).contains(&i);
            assert!(!between || !b.t.oc_out(0).unwrap(), "the pin high after word {i}");
        }
    }
    let first = b.high_for();
    assert!(first <= 96_000, "first pulse {first} cycles");
}

#[test]
fn the_stop_wins_over_a_command_waiting_in_the_preload() {
    // esc400 at full speed, a new (half) command preloaded for the next
    // frame; the stop comes 1 500 µs in: the pin falls at once, and the
    // next frame is the stop, not the waiting command
    let o = out("esc400", "1000");
    let mut b = Tim10::set_up(&o);
    run(&mut b, o.ccr(MAX as u32));
    b.after(2_500 * 96);
    run(&mut b, o.ccr(MAX as u32 / 2));
    assert!(b.after(1_500 * 96));
    stop(&mut b, &o);
    assert!(!b.after(96));
    b.after(1_000 * 96 - 96);
    let (high, _) = b.measure(96, 240_000);
    assert_eq!(high, 96_000, "the stop's 1 000 µs");
}

#[test]
fn setting_up_again_while_running_never_stretches_a_pulse() {
    // pwm at 1 kHz, 90 % duty, preloaded; 500 µs in, set up as esc50: the
    // pin falls at once and the first pulse after is the stop's 1 000 µs
    let o = out("pwm", "1000");
    let mut b = Tim10::set_up(&o);
    run(&mut b, o.ccr(MAX as u32 / 10 * 9));
    b.after(96_000);
    assert!(b.after(500 * 96));
    apply(&out("esc50", "1000").program(), &mut b).unwrap();
    let first = b.high_for();
    assert!(first <= 96_000, "first pulse {first} cycles");
}

#[test]
fn the_stop_never_lets_a_waiting_command_through_between_its_words() {
    // esc400 at half speed (1 500 µs), full speed waiting in the preload;
    // the stop comes 1 600 µs in, the pin already low. Word by word, the
    // waiting 2 000 µs is never in force (the model puts a waiting value
    // in force as OC1PE is cleared: with the preload cleared first, as a
    // first version did, the pin rose again for 400 µs)
    let o = out("esc400", "1000");
    let mut b = Tim10::set_up(&o);
    run(&mut b, o.ccr(MAX as u32 / 2));
    b.after(2_500 * 96);
    run(&mut b, o.ccr(MAX as u32));
    assert!(!b.after(1_600 * 96), "the half-speed pulse is over");
    for (i, op) in stop_ops(o.stop).iter().enumerate() {
        if let polyturn_firmware::regs::Op::Write(a, v) = *op {
            b.write(a, v);
            assert_ne!(b.t.active_ccr(0), o.ccr(MAX as u32), "the waiting command in force after word {i}");
            assert!(!b.after(96), "the pin high after word {i}");
        }
    }
}
