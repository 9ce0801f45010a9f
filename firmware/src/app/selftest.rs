//! The bench self-test's generator in the app: TIM9
//! plays the plan the controller judges (`polyturn_sync::selftest`), its
//! update interrupt applies `quadgen`'s programs verbatim, and the planning
//! executor copies its books to the controller every millisecond.
//!
//! The generator lives under the global critical section (BASEPRI, `cs.rs`),
//! which masks TIM9's interrupt (level 3) but never the tick: the handler
//! may take it for its whole run, and the tick waits for nothing of it.

use super::mmio::Mmio;
use super::tick;
use core::cell::RefCell;
use core::sync::atomic::{AtomicBool, Ordering};
use critical_section::Mutex;
use embassy_stm32::gpio::{AfType, Flex, Level, Output, OutputType, Pull, Speed};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::InterruptExt;
use embassy_stm32::peripherals as P;
use embassy_stm32::Peri;
use polyturn_firmware::quadgen::bench::{self, BenchGenerator};
use polyturn_firmware::quadgen::program::{self, Bus};
use polyturn_firmware::quadgen::AF;
use polyturn_sync::selftest::{Books, Verdict};

static GEN: Mutex<RefCell<Option<BenchGenerator>>> = Mutex::new(RefCell::new(None));
static PLAYING: AtomicBool = AtomicBool::new(false);

/// True while the generator plays: the once-a-second log keeps quiet.
pub fn playing() -> bool {
    PLAYING.load(Ordering::Relaxed)
}

/// A and B (PA2/PA3): inputs with pull-downs except while a test runs, so
/// a jumper to the lathe-encoder inputs never fights a real encoder.
pub struct Bench {
    a: Flex<'static>,
    b: Flex<'static>,
    /// the controller's run the generator plays
    playing: Option<u32>,
}

/// Boot: TIM9 clocked and stopped, the index (PA4) low, A and B idle, the
/// update interrupt enabled (TIM9 raises none until a test starts it).
pub fn init(a: Peri<'static, P::PA2>, b: Peri<'static, P::PA3>, index: Peri<'static, P::PA4>) -> Bench {
    embassy_stm32::rcc::enable_and_reset::<P::TIM9>();
    core::mem::forget(Output::new(index, Level::Low, Speed::High));
    let mut bench = Bench { a: Flex::new(a), b: Flex::new(b), playing: None };
    bench.pins_idle();
    // SAFETY: the handler below is ready, and GEN is empty.
    unsafe { interrupt::TIM1_BRK_TIM9.enable() };
    bench
}

impl Bench {
    fn pins_idle(&mut self) {
        self.a.set_as_input(Pull::Down);
        self.b.set_as_input(Pull::Down);
    }

    fn pins_timer(&mut self) {
        let t = AfType::output(OutputType::PushPull, Speed::High);
        self.a.set_as_af_unchecked(AF, t);
        self.b.set_as_af_unchecked(AF, t);
    }

    /// The planning executor's millisecond: start or stop the generator as
    /// the controller's run asks, and have its books judged. Under the
    /// tick's lock only copies (`selftest_pending`, `selftest_judged`); the
    /// judging runs between them.
    pub fn service(&mut self) {
        let want = tick::with_core(|c| c.selftest_plan()).flatten();
        match (want, self.playing) {
            (Some((id, _)), Some(p)) if id == p => {}
            (Some((id, plan)), _) => {
                self.stop();
                self.start(&plan);
                self.playing = Some(id);
            }
            (None, Some(_)) => return self.wind_down(),
            (None, None) => return,
        }
        let books = critical_section::with(|cs| GEN.borrow_ref(cs).as_ref().map(bench::books));
        let books = books.unwrap_or(Books { running: false, ..Books::default() });
        if let Some(mut pending) = tick::with_core(|c| c.selftest_pending()).flatten() {
            pending.judge(&books);
            tick::with_core(|c| c.selftest_judged(pending));
        }
    }

    /// The run has ended: after a pass the generator plays its last rest
    /// to the end (its parking period leaves A and B low, so the pins'
    /// pull-downs then move nothing); otherwise it stops at once.
    fn wind_down(&mut self) {
        let passed = tick::with_core(|c| c.selftest_report().is_some_and(|r| r.verdict == Verdict::Pass));
        let running = critical_section::with(|cs| GEN.borrow_ref(cs).as_ref().is_some_and(|g| g.running()));
        if !(passed == Some(true) && running) {
            self.stop();
        }
    }

    /// The start program, applied with TIM9's interrupt masked so the
    /// generator is in place for update event 0 (`quadgen` module docs);
    /// then the pins to the timer, which drives them low already.
    fn start(&mut self, plan: &polyturn_sync::selftest::Plan) {
        let Some((gen, init)) = bench::start(plan) else { return };
        critical_section::with(|cs| {
            GEN.borrow_ref_mut(cs).replace(gen);
            PLAYING.store(true, Ordering::Relaxed);
            let _ = program::apply(&init, &mut Mmio);
        });
        self.pins_timer();
    }

    /// Stops TIM9 where it is, index low, pins back to inputs.
    fn stop(&mut self) {
        critical_section::with(|cs| {
            let _ = program::apply(&program::STOP, &mut Mmio);
            GEN.borrow_ref_mut(cs).take();
            PLAYING.store(false, Ordering::Relaxed);
        });
        // (a test stopped early may leave A or B high: the pull-down then
        // moves the lathe count by a count or two, after the judging)
        self.pins_idle();
        self.playing = None;
    }
}

/// TIM9's update: the index level first (the only timed write, `quadgen`
/// module docs), prepared ahead; TIM9_CNT then says how late it came
/// (kept as the worst, in the books); then the flags and the next period's
/// values, also prepared ahead; last the work for the next update event.
/// An entry without UIF (RM0383 §14.4.4) is not an update event: nothing
/// moves on.
#[interrupt]
fn TIM1_BRK_TIM9() {
    critical_section::with(|cs| {
        let mut gen = GEN.borrow_ref_mut(cs);
        let Some(gen) = gen.as_mut() else {
            let _ = program::apply(&program::STOP, &mut Mmio);
            return;
        };
        let _ = program::apply(&[gen.index_op()], &mut Mmio);
        let ticks = Mmio.read(program::CNT);
        if Mmio.read(program::SR) & program::UIF == 0 {
            return;
        }
        gen.note_latency(ticks * (gen.current().psc as u32 + 1));
        let ops = gen.on_update();
        let _ = program::apply(&ops, &mut Mmio);
        gen.prepare();
    });
}
