//! The machine behind the fake board (tests, the web page's): time passes between the
//! host's commands, the lathe turns at a set speed with an index every
//! `cpr` counts, and the step output emits what each tick planned two
//! ticks later (`steps::pipe`), so jogs and the encoder check really run.
//! With `drive bldc` the cutter is idealised: its encoder turns each tick
//! by the speed the tick commanded (`sim::bldc_drive` models a real drive).

use polyturn_firmware::quadgen::bench::playback::{Event, Playback};
use polyturn_firmware::quadgen::{bench, TIMER_HZ};
use polyturn_sync::{Controller, TickInput};
use std::f64::consts::TAU;

use polyturn_host::sim::lathe::{Lathe, LatheProfile, Leg};

/// The control tick's rate (the firmware's).
pub const TICK_HZ: u32 = polyturn_sync::Timing::FIRMWARE.tick_hz;

/// Control ticks in `ms` milliseconds of the board.
pub const fn ticks_in_ms(ms: u64) -> usize {
    (ms * TICK_HZ as u64 / 1_000) as usize
}

/// The machinist's hand rests this long on the chuck before turning it for
/// the encoder check.
const HAND_RESTS_TICKS: usize = ticks_in_ms(1_200);

/// How fast the spindle reaches a new set speed: a lathe's motor takes
/// about a second to reach 600 rpm, so the sync core sees a ramp, not a jump.
const SPINDLE_ACCEL_RPM_PER_S: f64 = 600.0;

/// The lathe under power at a set speed (the simulator's spindle model,
/// `sim::lathe`), and where its encoder stood when it was set.
struct Spindle {
    lathe: Lathe,
    set_rpm: f64,
    /// the lathe's count, in thousandths, when this speed was set
    from_milli: i64,
}

/// A hand turning the chuck: a turn in about 2 s.
const HAND_TURN_S: f64 = 2.0;

/// TIM9 cycles per control tick.
const CYCLES_PER_TICK: u64 = (TIMER_HZ / TICK_HZ) as u64;

/// The self-test's generator, jumpered to the lathe input: the
/// controller's run it plays, the player, and TIM9's cycles so far.
struct Jumpered {
    run: u32,
    player: Playback,
    cycles: u64,
}

pub struct Workshop {
    /// control ticks that pass before each command line is handled
    pub ticks_per_line: usize,
    /// the hand's speed on the chuck, thousandths of a count a tick
    /// (`turn_at`)
    counts_per_tick_x1000: i64,
    /// the encoder's real counts per turn (its index comes once a turn)
    pub cpr: i64,
    /// the machinist's hand on the chuck: before the line that ends an
    /// encoder check, the lathe rests 1.2 s and then turns at the hand's
    /// speed (`turn_at`); at any other time it rests
    pub turn_for_check: bool,
    /// with `turn_for_check`, the ticks before the line that ends the
    /// check, if more than `ticks_per_line`: the machinist's hand takes its
    /// time on the chuck, and quick answers elsewhere
    pub check_ticks: usize,
    lathe_milli: i64,
    /// thousandths of a count the hand has still to turn the chuck by
    /// (`turn_by_hand`)
    hand_milli: i64,
    /// counts the self-test's generator made, and the index it latched
    played: i64,
    played_index: Option<u16>,
    jumpered: Option<Jumpered>,
    spindle: Option<Spindle>,
    emitted: u16,
    pipe: [u16; 2],
    /// the BLDC cutter's encoder, Q16 counts
    bldc_q16: i64,
    t: usize,
}

impl Workshop {
    pub fn new(ticks_per_line: usize) -> Workshop {
        Workshop {
            ticks_per_line,
            counts_per_tick_x1000: 0,
            cpr: 2400,
            turn_for_check: false,
            check_ticks: 0,
            lathe_milli: 0,
            hand_milli: 0,
            played: 0,
            played_index: None,
            jumpered: None,
            spindle: None,
            emitted: 0,
            pipe: [0; 2],
            bldc_q16: 0,
            t: 0,
        }
    }

    /// The machinist's hand turns the lathe at `counts_per_s` (forward; 0
    /// rests it), in whole thousandths of a count a control tick: a speed
    /// between two is rounded down.
    pub fn turn_at(&mut self, counts_per_s: u32) {
        self.counts_per_tick_x1000 = i64::from(counts_per_s) * 1_000 / i64::from(TICK_HZ);
    }

    pub fn run(&mut self, ctl: &mut Controller, line: &str) {
        let checking = self.turn_for_check && line.contains("check-encoder stop");
        let n = if checking { self.ticks_per_line.max(self.check_ticks) } else { self.ticks_per_line };
        self.ticks(ctl, n, checking);
    }

    /// Runs the lathe under power toward `rpm` (forward; 0 stops it), as a
    /// machinist sets the lathe's speed: it ramps there and holds it until
    /// the next call. Once it rests at 0 the hand on the chuck is back
    /// (`turn_for_check`).
    pub fn set_lathe_rpm(&mut self, rpm: f64) {
        let now_rpm = self.spindle.as_ref().map_or(0.0, |s| s.lathe.speed / TAU * 60.0);
        if rpm <= 0.0 && now_rpm == 0.0 {
            self.spindle = None;
            return;
        }
        let leg = Leg { rpm: rpm.max(0.0), accel_rpm_per_s: SPINDLE_ACCEL_RPM_PER_S, hold_s: f64::INFINITY };
        let profile = LatheProfile { start_rpm: now_rpm, legs: vec![leg], ripple: 0.0, wander: 0.0, dips: vec![] };
        self.spindle =
            Some(Spindle { lathe: Lathe::new(profile, 1), set_rpm: rpm.max(0.0), from_milli: self.lathe_milli });
    }

    /// The machinist turns the chuck by hand by `counts` (either way), at a
    /// hand's pace, as time passes on the board (`run`, `pass`); a turn
    /// asked for before the last has ended adds to it.
    pub fn turn_by_hand(&mut self, counts: i64) {
        self.hand_milli += counts * 1000;
    }

    /// The hand's next tick: thousandths of a count it turns the chuck by;
    /// None once it has turned by all it was asked.
    fn hand_tick(&mut self) -> Option<i64> {
        let pace = (self.cpr as f64 * 1000.0 / (HAND_TURN_S * f64::from(TICK_HZ))) as i64;
        let step = self.hand_milli.clamp(-pace, pace);
        self.hand_milli -= step;
        (step != 0).then_some(step)
    }

    /// The lathe's speed now, rpm (0 when no speed is set).
    pub fn lathe_rpm(&self) -> f64 {
        self.spindle.as_ref().map_or(0.0, |s| s.lathe.speed / TAU * 60.0)
    }

    /// The spindle's next tick: thousandths of a count it turns by; None
    /// when no speed is set (the lathe rests or turns by hand).
    fn spindle_tick(&mut self) -> Option<i64> {
        let s = self.spindle.as_mut()?;
        s.lathe.advance(1.0 / TICK_HZ as f64);
        let at = s.from_milli + (s.lathe.angle / TAU * self.cpr as f64 * 1000.0).round() as i64;
        let step = at - self.lathe_milli;
        if s.set_rpm == 0.0 && s.lathe.speed == 0.0 {
            self.spindle = None; // at rest: back to the hand on the chuck
        }
        Some(step)
    }

    /// `ticks` control ticks pass with no command (a `watch` line's wait).
    pub fn pass(&mut self, ctl: &mut Controller, ticks: usize) {
        self.ticks(ctl, ticks, false);
    }

    fn ticks(&mut self, ctl: &mut Controller, ticks: usize, checking: bool) {
        for i in 0..ticks {
            let before = self.lathe_milli / 1000;
            let turning = !self.turn_for_check || (checking && i >= HAND_RESTS_TICKS);
            if let Some(step) = self.spindle_tick().or_else(|| self.hand_tick()) {
                self.lathe_milli += step;
            } else if turning {
                self.lathe_milli += self.counts_per_tick_x1000;
            }
            let now = self.lathe_milli / 1000;
            // the index at count 5 of every turn, latched as it passes
            let index = (before.min(now) + 1..=before.max(now)).find(|c| c.rem_euclid(self.cpr) == 5).map(|c| c as u16);
            self.play();
            let lathe = (now + self.played) as u16;
            let index = index.or(self.played_index.take());
            let cutter = (self.bldc_q16 >> 16) as u16;
            let out = ctl.tick(&TickInput { lathe, index, emitted: self.emitted, cutter, ..TickInput::default() });
            self.bldc_q16 += out.speed_q16 as i64;
            self.emitted = self.emitted.wrapping_add(self.pipe[self.t % 2]);
            self.pipe[self.t % 2] = out.plan.count;
            self.t += 1;
            if self.t.is_multiple_of(ticks_in_ms(1)) {
                self.feed_books(ctl);
                ctl.service();
            }
        }
    }

    /// One tick of the self-test's generator, as the app's sampler starts it.
    fn play(&mut self) {
        let Some(j) = &mut self.jumpered else { return };
        j.cycles += CYCLES_PER_TICK;
        let (played, latched) = (&mut self.played, &mut self.played_index);
        let base = self.lathe_milli / 1000;
        j.player.play(j.cycles, |_, e| match e {
            Event::Count(d) => *played += d as i64,
            Event::Index => *latched = Some((base + *played) as u16),
        });
    }

    /// The app's millisecond: start, stop and feed the generator (`app::selftest`).
    fn feed_books(&mut self, ctl: &mut Controller) {
        match (ctl.selftest_plan(), &self.jumpered) {
            (Some((run, _)), Some(j)) if j.run == run => {}
            (Some((run, plan)), _) => {
                self.jumpered = bench::start(&plan).map(|(g, _)| Jumpered { run, player: Playback::new(g), cycles: 0 });
            }
            (None, _) => self.jumpered = None,
        }
        if let Some(j) = &self.jumpered {
            ctl.selftest_books(&bench::books(j.player.generator()));
        }
    }
}
