//! Scenario (h): each BLDC interface (`bldc-out`) on the real image. The
//! image boots on the hexagon's settings with `drive bldc` and the
//! interface saved; the lathe turns and the cutter is engaged. TIM10 must
//! make the interface's frame (from its PSC and ARR, RM0383 §14.3.1: a
//! frame is (PSC + 1)(ARR + 1) timer clocks) and a running command; BLDC_DIR
//! (PB1) the wired sense. Then the E-stop opens while the drive runs, just
//! after a frame's update: within 50 µs, with no update between, PB8 must
//! be low (the pulse under way cut, not left to its preloaded end), and
//! from the next frame the compare in force (what the pin follows) must be
//! the stop. On a second boot the drive runs on: the emulator
//! turns no cutter, so its encoder stands still and the core's stall check
//! must stop the drive (a fault), ENABLE inactive. The stop is a 1 000 µs pulse for an
//! RC ESC, 125 µs for OneShot125, no pulse for a PWM. The expected frames
//! and stops are the interfaces' published figures, written here, not
//! taken from the firmware. (The E-stop interrupt's own write of the stop,
//! before any tick, is the probe scenario's: `probe::fire`.)

use super::{lathe, press, scenario, settings, ENGAGE, ESTOP, GPIOB, MS, SYSCLK};
use crate::checks::Report;
use crate::image::Image;
use crate::machine::Machine;
use polyturn_stm32_model::addr::off;
use polyturn_stm32_model::Params;
use std::rc::Rc;

/// (setting, frame µs, stop pulse µs)
const INTERFACES: [(&str, u64, u64); 4] =
    [("esc50", 20_000, 1_000), ("esc400", 2_500, 1_000), ("oneshot125", 500, 125), ("pwm", 1_000, 0)];

struct Seen {
    frame_us: f64,
    running_us: f64,
    /// PB8 high as the E-stop opened, just after an update, and low 50 µs
    /// later in the same frame
    cut: Option<bool>,
    /// the compare in force a frame later
    stop_us: f64,
    dir: Option<bool>,
    /// CCR1 after the stall (µs), ENABLE then, and its inactive level
    stalled_us: f64,
    stall_disabled: bool,
    safe: bool,
}

/// TIM10's frame and the compare in force (what the pin follows), in µs
/// of its kernel clock.
fn tim10_us(m: &mut Machine) -> (f64, f64) {
    let c = m.chip();
    let clk = c.rcc.apb2().1 as f64;
    let t = &c.gp[3];
    let tick_us = (t.get(off::PSC) as f64 + 1.0) / clk * 1e6;
    ((t.get(off::ARR) as f64 + 1.0) * tick_us, t.active_ccr(0) as f64 * tick_us)
}

/// The image booted on the hexagon's settings with `drive bldc` and
/// `name`, the lathe at speed, the cutter engaged and followed 100 ms: the
/// widest command pulse in force over that time.
fn engaged(image: &Rc<Image>, name: &str) -> Result<(Machine, f64), String> {
    let spec = &super::super::jobs::SPECS[0]; // the hexagon's
    let sc = scenario(spec);
    let cfg = sc.core.with("drive", "bldc").and_then(|c| c.with("bldc-out", name));
    let cfg = cfg.map_err(|e| format!("{}: {}", e.field, e.allowed))?;
    let mut m = Machine::new(image.clone(), Params::default(), &settings::saved(&cfg)?)?;
    m.cpr = cfg.encoder_counts_per_rev;
    m.drive(GPIOB, ESTOP, Some(false));
    m.run(100 * MS);
    let now = m.chip().now;
    m.lathe = Some(lathe::LatheDrive::motor(sc.lathe.clone(), spec.seed, cfg.encoder_counts_per_rev, now, SYSCLK));
    m.run(600 * MS); // at speed
    press(&mut m, ENGAGE);
    let mut running_us = 0.0f64;
    for _ in 0..100 {
        m.run(MS);
        running_us = running_us.max(tim10_us(&mut m).1);
    }
    Ok((m, running_us))
}

fn one(image: &Rc<Image>, name: &str) -> Result<(Seen, u64), String> {
    // the E-stop while the drive runs
    let (mut m, running_us) = engaged(image, name)?;
    let (frame_us, _) = tim10_us(&mut m);
    let dir = m.chip().gpio[1].pin_out(1);
    // just after a frame's update, and judged 50 µs later: the next update
    // is a frame away, so a stop left in the preload would still show the
    // running command
    let updates = |m: &mut Machine| {
        m.chip().sync();
        m.chip().gp[3].updates
    };
    let before = updates(&mut m);
    while updates(&mut m) == before {
        m.run(MS / 100);
    }
    m.chip().sync();
    let high_before = m.chip().gp[3].oc_out(0) == Some(true);
    m.drive(GPIOB, ESTOP, None);
    m.run(MS / 20);
    m.chip().sync();
    // high at the E-stop, low 50 µs on
    let cut = m.chip().gp[3].oc_out(0).map(|high| high_before && !high);
    let safe = m.chip().outputs().safe_now();
    m.run((frame_us * (SYSCLK / 1_000_000) as f64) as u64); // to 50 µs into the next frame
    let stop_us = tim10_us(&mut m).1;
    let mut cycles = m.chip().now;
    // a fault: 0.2 s commanded with the encoder still, `Fault::Stall`
    let (mut m, _) = engaged(image, name)?;
    m.run(600 * MS);
    let stalled_us = tim10_us(&mut m).1;
    let o = m.chip().outputs();
    let stall_disabled = o.enable == Some(o.enable_inactive);
    cycles += m.chip().now;
    Ok((Seen { frame_us, running_us, cut, stop_us, dir, stalled_us, stall_disabled, safe }, cycles))
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let mut total = 0;
    for (name, frame_us, stop_us) in INTERFACES {
        let (s, cycles) = one(image, name)?;
        total += cycles;
        let close = |a: f64, b: f64| (a - b).abs() < 0.01;
        let ok = close(s.frame_us, frame_us as f64)
            && s.running_us > stop_us as f64
            && s.cut == Some(true)
            && close(s.stop_us, stop_us as f64)
            && s.dir == Some(false)
            && close(s.stalled_us, stop_us as f64)
            && s.stall_disabled
            && s.safe;
        let text = format!(
            "TIM10 frame {:.1} µs (want {frame_us}), widest command pulse {:.1} µs while following, BLDC_DIR {:?} (dir same: low); after the stall {:.1} µs, ENABLE inactive {}; PB8 high as the E-stop opened and low 50 µs after (no frame's update between) {:?}, a frame later {:.1} µs (the stop: {stop_us}), outputs safe: {}",
            s.frame_us, s.running_us, s.dir, s.stalled_us, s.stall_disabled, s.cut, s.stop_us, s.safe
        );
        r.line(ok, &format!("bldc {name}"), &text);
    }
    Ok(total)
}
