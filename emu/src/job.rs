//! Jobs run on the real image the way a machinist runs them: settings saved in
//! flash before boot, the E-stop closed, the lathe turning the encoder, ENGAGE and
//! STOP pressed on their pins, and STEP/DIR judged at the pins by the driver model
//! the step-output tests use (`polyturn_bench::hwsim::driver`).

pub mod bldc;
pub mod busy;
pub mod damaged;
pub mod divide;
pub mod edgecheck;
pub mod estop;
pub mod host;
pub mod lathe;
pub mod lost;
pub mod planlate;
pub mod replay;
pub mod save;
pub mod selftest;
pub mod settings;

use crate::image::Image;
use crate::machine::Machine;
use polyturn_bench::hwsim::driver::{receive, Received};
use polyturn_host::geometry::{Direction, Setup};
use polyturn_host::sim::{Scenario, Start};
use polyturn_stm32_model::Params;
use polyturn_sync::{Config, DriveKind, Ratio};
use std::rc::Rc;
use std::time::Instant;

pub const MS: u64 = 96_000;
pub(crate) const SYSCLK: u64 = 96_000_000;
/// Key pins (board.rs): ENGAGE PB12, STOP PB10; E-stop PB14.
pub const ENGAGE: u8 = 12;
const STOP: u8 = 10;
pub const ESTOP: u8 = 14;
pub const GPIOB: usize = 1;

/// What happens during the job.
#[derive(Clone, Copy, PartialEq)]
pub enum Kind {
    /// the lathe runs its profile; STOP afterwards
    Cut,
    /// the E-stop opens `at_s` after engaging, then closes again
    EStop { at_s: f64 },
    /// the chuck is rocked by hand, ±40 counts at 3 Hz for 2 s
    Rock,
    /// `at_s` after engaging the tick is held off for `hold_us`, as a
    /// thread-mode section at its level would: updates merge, ticks are lost
    LostTick { at_s: f64, hold_us: u64 },
    /// `at_s` after engaging, the step plan a tick leaves is not made by the
    /// next tick (`planlate`)
    LatePlan { at_s: f64, how: planlate::How },
    /// at the top step rate, the console busy all through (`busy`)
    Busy,
}

pub struct Spec {
    pub name: &'static str,
    pub kind: Kind,
    /// the reading of DMA2 stream 5's NDTR the model follows (the step output must
    /// work on both: `NdtrReading`)
    pub ndtr: polyturn_stm32_model::NdtrReading,
    /// the count TIM3's capture takes on A's rise (the edge times must work on
    /// both: `EncoderCapture`)
    pub capture: polyturn_stm32_model::EncoderCapture,
    /// how long the lathe turns before ENGAGE when it starts spinning
    pub engage_after_ms: u64,
    pub ratio: &'static str,
    pub edges: u32,
    pub rpm: f64,
    pub ripple: f64,
    pub turns: f64,
    pub start: Start,
    pub seed: u64,
}

pub struct Outcome {
    pub name: &'static str,
    pub mcu_s: f64,
    pub wall_s: f64,
    pub received: Received,
    /// the gear's exact steps per lathe count
    pub exact_per_count: f64,
    pub lathe_count: i64,
    pub tim3_cnt: u32,
    pub dir_setup: u64,
    pub faults: Vec<String>,
    pub config: Config,
    /// the lathe's count when ENGAGE went down
    pub engage_count: i64,
    pub estop: Option<crate::job::estop::Seen>,
    /// the tick handler: average and worst cycles, entry to return (the
    /// model's, and the bound's)
    pub tick: (f64, u64),
    pub tick_bound: (f64, u64),
    pub plan_bound: (f64, u64),
    /// flash misses (instruction, literal), the model's and the bound's
    pub misses: [(u64, u64); 2],
    pub tick_all: Vec<(u64, u64)>,
    pub plan_all: Vec<(u64, u64)>,
    /// the longest interrupts-off (PRIMASK) section in thread mode, cycles on the bound:
    /// what can delay the E-stop
    pub irq_off: u64,
    /// the longest thread-mode section holding off the running tick (its lock),
    /// cycles on the bound
    pub tick_lock: u64,
    /// where it began (the function)
    pub tick_lock_at: String,
    /// the step stream against the host core fed the image's own tick inputs
    pub replay: Option<replay::Replay>,
    /// the edge times the image's tick read (`edges`)
    pub edges: Option<edgecheck::EdgeCheck>,
    /// ticks lost: as the image counted them (`app::tick::TICKS_LOST`), and
    /// as the emulator saw them (updates no handler answered)
    pub ticks_lost: lost::Counted,
    /// a lost-tick job's hold (`Kind::LostTick`)
    pub held: Option<lost::Held>,
    /// the step plan's handler: average and worst cycles (the model's), entry to
    /// return, and the plans the image found late (`app::tick::plan::LATES`)
    pub plan: (f64, u64),
    pub plans_late: Option<u32>,
    /// a late-plan job's cause (`Kind::LatePlan`)
    pub late: Option<planlate::Late>,
    /// the console's answers through a busy job (`Kind::Busy`)
    pub answers: Option<busy::Answers>,
}

fn setup(s: &Spec) -> Setup {
    let ratio = Ratio::parse(s.ratio).expect("a valid ratio");
    Setup {
        cutter_radius_mm: 50.0,
        stock_radius_mm: 10.0,
        depth_mm: 1.5,
        ratio,
        edges: s.edges,
        direction: Direction::Same,
    }
}

/// The host simulator's scenario for the same job (its lathe profile and settings).
pub fn scenario(s: &Spec) -> Scenario {
    let mut sc =
        Scenario::standard(setup(s), s.rpm, s.turns, s.ripple, s.start, 2400, 3200, DriveKind::Stepper, s.seed);
    sc.lathe.legs[0].hold_s = s.turns * 60.0 / s.rpm;
    if s.kind == Kind::Busy {
        busy::top_rate(&mut sc.core);
    }
    sc
}

/// Holds a key down for 60 ms (3 × the debounce, `keys::DEBOUNCE_MS`), then lets go.
pub(crate) fn press(m: &mut Machine, pin: u8) {
    m.drive(GPIOB, pin, Some(false));
    m.run(60 * MS);
    m.drive(GPIOB, pin, None);
    m.run(40 * MS);
}

/// `POLYTURN_EMU_PROFILE`: the run profiled by function, within
/// `POLYTURN_EMU_PROFILE_FROM_MS`..`_TO_MS` of MCU time when given.
fn profile_from_env(m: &mut Machine) {
    if std::env::var_os("POLYTURN_EMU_PROFILE").is_none() {
        return;
    }
    let ms = |v: &str| std::env::var(v).ok().and_then(|s| s.parse::<f64>().ok()).map(|t| (t * 96e3) as u64);
    let window = ms("POLYTURN_EMU_PROFILE_FROM_MS").unwrap_or(0)..ms("POLYTURN_EMU_PROFILE_TO_MS").unwrap_or(u64::MAX);
    let mut p = crate::clock::profile::Profile::default();
    p.window = window;
    m.chip().profile = Some(p);
}

/// Runs until the lathe's profile ends or a fault stops the run; with
/// `busy`, the console kept busy every 100 ms (`busy::slice`), its answers
/// returned.
fn until_the_lathe_stops(m: &mut Machine, busy: bool) -> Option<busy::Answers> {
    let mut answers = busy.then(busy::Answers::default);
    let mut k = 0;
    while !m.lathe.as_ref().is_some_and(|l| l.finished()) && m.chip().faults.is_empty() {
        match answers.as_mut() {
            Some(a) => {
                let t = m.chip().now;
                busy::slice(m, k, a);
                let left = (t + 100 * MS).saturating_sub(m.chip().now).max(MS);
                m.run(left);
                k += 1;
            }
            None => m.run(10 * MS),
        }
    }
    answers
}

/// Whether the job's ticks can be replayed on the host core: not where the
/// job stops the tick's flow (the replay follows one edge clock from the
/// start, and a lost tick has it measured again; a late plan that misses
/// its window stops the cutter), nor where the console changes the phase,
/// which the replay does not follow.
fn replayable(kind: Kind) -> bool {
    match kind {
        Kind::EStop { .. } | Kind::LostTick { .. } | Kind::Busy => false,
        Kind::LatePlan { how, .. } => !how.misses(),
        _ => true,
    }
}

pub fn run(image: &Rc<Image>, spec: &Spec) -> Result<Outcome, String> {
    let params = Params { ndtr: spec.ndtr, encoder_capture: spec.capture, ..Params::default() };
    let wall = Instant::now();
    let sc = scenario(spec);
    let flash = settings::saved(&sc.core)?;
    let mut m = Machine::new(image.clone(), params, &flash)?;
    m.cpr = sc.core.encoder_counts_per_rev;
    profile_from_env(&mut m);
    if replayable(spec.kind) {
        m.chip().tape = Some(crate::chip::tape::Tape::default());
    }
    m.drive(GPIOB, ESTOP, Some(false));
    m.run(100 * MS);
    if matches!(spec.kind, Kind::EStop { .. } | Kind::Busy) {
        // the fault is cleared on the console, or the console kept busy:
        // plug the USB host in
        m = crate::usb::scenario::enumerate_on(m)?.0;
    }
    let cpr = sc.core.encoder_counts_per_rev;
    let lathe = |m: &mut Machine| {
        let now = m.chip().now;
        m.lathe = Some(match spec.kind {
            Kind::Rock => lathe::LatheDrive::new(
                lathe::Motion::Rock { amp_counts: 40.0, hz: 3.0, secs: 2.0, t: 0.0 },
                cpr,
                now,
                SYSCLK,
            ),
            _ => lathe::LatheDrive::motor(sc.lathe.clone(), spec.seed, cpr, now, SYSCLK),
        });
    };
    if spec.start == Start::Rest {
        press(&mut m, ENGAGE);
        lathe(&mut m);
    } else {
        lathe(&mut m);
        m.run(spec.engage_after_ms * MS);
    }
    let engage_count = m.lathe.as_ref().map_or(0, |l| l.count);
    if spec.start != Start::Rest {
        press(&mut m, ENGAGE);
    }
    let estop = match spec.kind {
        Kind::EStop { at_s } => Some(estop::open_mid_cut(&mut m, at_s, &sc.core)),
        _ => None,
    };
    let held = match spec.kind {
        Kind::LostTick { at_s, hold_us } => Some(lost::hold(&mut m, at_s, hold_us)),
        _ => None,
    };
    let late = match spec.kind {
        Kind::LatePlan { at_s, how } => Some(planlate::cause(&mut m, at_s, how)),
        _ => None,
    };
    let answers = until_the_lathe_stops(&mut m, spec.kind == Kind::Busy);
    m.run(100 * MS);
    // compared up to STOP: the key task's disengage shows on no pin
    let until = m.chip().now;
    press(&mut m, STOP);
    let mut o = outcome(&mut m, spec, &sc.core, wall);
    let clock = m.edge_clock();
    let c = m.chip();
    if let Some(mut t) = c.tape.take() {
        t.edge_clock = clock.map(|k| k.0);
        o.edges = Some(edgecheck::judge(&t, clock.map(|k| k.1)));
        o.replay = Some(replay::compare(&sc.core, &t, c.mcu.edges(), until));
    }
    o.engage_count = engage_count;
    o.estop = estop;
    o.ticks_lost = lost::counted(&mut m);
    o.plans_late = planlate::lates(&m);
    o.held = held.map(|h| h.judged(&mut m));
    o.late = late.map(|l| l.judged(&mut m));
    o.answers = answers;
    Ok(o)
}

impl Outcome {
    /// The gear's position at the end less the net steps, reduced by whole
    /// cutter turns (engaging catches up at most half a turn: `drop_whole_turns`).
    /// The gear counts from 0 at boot, or from the first index if the lathe passed
    /// one before the first engagement (`Controller::gear_origin`).
    pub fn phase_error_steps(&self) -> f64 {
        let cpr = self.config.encoder_counts_per_rev as i64;
        let origin = if self.engage_count >= cpr { cpr } else { 0 };
        let m = self.config.motor_steps_per_rev as f64;
        let diff = self.received.steps as f64 - self.exact_per_count * (self.lathe_count - origin) as f64;
        diff - m * (diff / m).round()
    }
}

/// The profile's top functions for the tick and its plan (`--profile`).
fn print_profile(m: &mut Machine) {
    let image = m.image.clone();
    let Some(p) = m.chip().profile.take() else { return };
    for (what, exc) in [("tick", crate::chip::probe::tick_exc()), ("plan", crate::chip::probe::plan_exc())] {
        if let Some(dir) = std::env::var_os("POLYTURN_EMU_PROFILE") {
            let lines: Vec<String> = p.blocks(exc).iter().map(|b| format!("{:#x} {} {}", b.0, b.1, b.2)).collect();
            let _ = std::fs::write(std::path::Path::new(&dir).join(format!("{what}.blocks")), lines.join("\n"));
        }
        println!("  profile of the {what} (function: model, bound cycles in all):");
        for (f, model, bound) in p.functions(exc, |a| image.func_at(a)).iter().take(25) {
            println!("    {bound:>12} {model:>12}  {f}");
        }
    }
}

fn outcome(m: &mut Machine, spec: &Spec, cfg: &Config, wall: Instant) -> Outcome {
    print_profile(m);
    let image = m.image.clone();
    let d = polyturn_sync::derived::Derived::new(cfg, polyturn_sync::Timing::FIRMWARE);
    let (pulse, dir_setup) = (d.steps.pulse as u64, d.steps.dir_setup as u64);
    let received = receive(m.chip().mcu.edges(), pulse, true);
    let count = m.lathe.as_ref().map_or(0, |l| l.count);
    let r = cfg.ratio;
    let per_count =
        r.num() as f64 * cfg.motor_steps_per_rev as f64 / (r.den() as f64 * cfg.encoder_counts_per_rev as f64);
    let c = m.chip();
    Outcome {
        name: spec.name,
        mcu_s: c.now as f64 / SYSCLK as f64,
        wall_s: wall.elapsed().as_secs_f64(),
        received,
        exact_per_count: per_count,
        lathe_count: count,
        tim3_cnt: c.gp[0].read(polyturn_stm32_model::addr::off::CNT),

        dir_setup,
        faults: c.faults.iter().map(|f| f.1.clone()).collect(),
        config: *cfg,
        engage_count: 0,
        estop: None,
        tick: (c.probe.tick.average(), c.probe.tick.worst),
        tick_bound: (c.probe.tick.average_bound(), c.probe.tick.worst_bound),
        plan_bound: (c.probe.plan.average_bound(), c.probe.plan.worst_bound),
        misses: c.meter.misses(),
        tick_all: std::mem::take(&mut c.probe.tick.all),
        plan_all: std::mem::take(&mut c.probe.plan.all),
        irq_off: c.primask.longest.bound,
        tick_lock: c.tickmask.ticking.bound,
        tick_lock_at: format!(
            "{} called from {}",
            image.func_at(c.tickmask.ticking.pc),
            image.func_at(c.tickmask.ticking.caller)
        ),
        replay: None,
        edges: None,
        ticks_lost: lost::Counted::default(),
        held: None,
        plan: (c.probe.plan.average(), c.probe.plan.worst),
        plans_late: None,
        late: None,
        answers: None,
    }
}
