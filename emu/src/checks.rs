//! The checks, each printing one PASS/FAIL line with its figures.

use crate::chip::pins::Outputs;
use crate::machine::Machine;
use crate::svd;
use polyturn_firmware::board;
use polyturn_stm32_model::addr::{off, TIM11};
use polyturn_stm32_model::chip::gpio::{MODER, PUPDR};

/// Instructions (about 10 ms at 96 MHz) within which boot must reach the main loop.
const BOOT_BOUND: u64 = 1_000_000;
/// Handler runs allowed off the rate over the window.
const TICK_TOLERANCE: f64 = 1.0;

#[derive(Default)]
pub struct Report {
    pub failed: u32,
}

impl Report {
    pub fn line(&mut self, ok: bool, name: &str, text: &str) -> bool {
        self.failed += !ok as u32;
        println!("{} {name:<18} {text}", if ok { "PASS" } else { "FAIL" });
        ok
    }
}

pub fn faults(m: &mut Machine) -> String {
    let f: Vec<String> = m.chip().faults.iter().map(|f| f.1.clone()).collect();
    if f.is_empty() {
        "none".into()
    } else {
        f.join("; ")
    }
}

pub fn boot(r: &mut Report, m: &mut Machine, led_out: Option<u64>) {
    let sysclk = board::SYSCLK_HZ as f64;
    let c = m.chip();
    let (started, pets) = (c.iwdg.started_at(), c.iwdg.pets());
    let now = c.now;
    let gap = c.iwdg.longest_gap(started.unwrap_or(now), now);
    let ok = c.faults.is_empty()
        && started.is_some_and(|s| s <= BOOT_BOUND)
        && led_out.is_some_and(|t| t <= BOOT_BOUND)
        && !pets.is_empty();
    let text = format!(
        "watchdog started at cycle {started:?} (bound {BOOT_BOUND}), {} pets by cycle {now} (longest gap {:.1} ms), LED PC13 output at cycle {led_out:?}; faults: {}",
        pets.len(),
        gap as f64 / sysclk * 1e3,
        faults(m)
    );
    r.line(ok, "boot", &text);
}

fn tick_rate(m: &mut Machine) -> f64 {
    let c = m.chip();
    let (psc, arr) = (c.mcu.read(TIM11 + off::PSC), c.mcu.read(TIM11 + off::ARR));
    c.rcc.apb2().1 as f64 / ((psc as f64 + 1.0) * (arr as f64 + 1.0))
}

pub fn registers(r: &mut Report, m: &mut Machine) {
    let mut bad = Vec::new();
    let c = m.chip();
    for p in board::PINS {
        let (port, i) = p.port_and_index();
        let g = &c.gpio[(port as u8 - b'A') as usize];
        let got = (g.field(MODER, i), p.mode.af().map(|_| g.afr(i)), g.field(PUPDR, i));
        let want = (p.mode.moder(), p.mode.af().map(u32::from), p.pull.pupdr());
        if got != want {
            bad.push(format!("{} {}: MODER/AFR/PUPDR {got:?}, board.rs {want:?}", p.signal, p.pin));
        }
    }
    for (name, level) in board::PRIORITIES {
        let n = svd::irq(name);
        let (got, want) = (c.nvic.prio[16 + n], level << 4);
        if got != want || !c.nvic.enabled[n] {
            bad.push(format!("{name} (IRQ {n}): IPR {got:#04x} enabled={}, board.rs {want:#04x}", c.nvic.enabled[n]));
        }
    }
    // nothing else enabled at or above the tick's level: it would delay the tick,
    // or race the state app/cs.rs's BASEPRI section protects; the E-stop above it;
    let tick = svd::irq(board::TICK_IRQ);
    let estop = svd::irq(board::ESTOP_IRQ);
    if c.nvic.prio[16 + estop] >= c.nvic.prio[16 + tick] {
        bad.push("the E-stop does not pre-empt the tick".to_string());
    }
    // and the step plan next below the tick, alone at its level: it takes no
    // lock, and app/cs.rs masks only the levels below it
    let plan = svd::irq(board::PLAN_IRQ);
    if c.nvic.prio[16 + plan] <= c.nvic.prio[16 + tick] {
        bad.push("the tick does not pre-empt its step plan".to_string());
    }
    let allowed = [tick, estop, plan];
    let crowd: Vec<usize> = (0..c.nvic.enabled.len())
        .filter(|&n| c.nvic.enabled[n] && c.nvic.prio[16 + n] <= c.nvic.prio[16 + plan] && !allowed.contains(&n))
        .collect();
    if !crowd.is_empty() {
        bad.push(format!("enabled at the tick's or its plan's level: IRQs {crowd:?}"));
    }
    let sysclk = c.sysclk();
    if sysclk != board::SYSCLK_HZ as u64 {
        bad.push(format!("SYSCLK {sysclk}, board.rs {}", board::SYSCLK_HZ));
    }
    let (apb1, apb2) = (c.rcc.apb1(), c.rcc.apb2());
    let rate = tick_rate(m);
    if rate != board::TICK_HZ as f64 {
        bad.push(format!("tick {rate:.1} Hz, board.rs {}", board::TICK_HZ));
    }
    bad.extend(edge_time_words(m));
    let misplaced = svd::misplaced_handlers(&m.image);
    if !misplaced.is_empty() {
        bad.push(format!("handlers not at their SVD vectors: {misplaced:?}"));
    }
    let mhz = |v: u64| v as f64 / 1e6;
    let text = format!(
        "{} pins, {} priorities, SYSCLK {:.0} MHz (APB1 {:.0}/{:.0} MHz timers, APB2 {:.0}/{:.0}), tick {rate:.0} Hz{}",
        board::PINS.len(),
        board::PRIORITIES.len(),
        mhz(sysclk),
        mhz(apb1.0),
        mhz(apb1.1),
        mhz(apb2.0),
        mhz(apb2.1),
        if bad.is_empty() { String::new() } else { format!("; {}", bad.join("; ")) }
    );
    r.line(bad.is_empty(), "registers", &text);
}

/// The MPU as the image left it after boot (the model's reading, ARM DUI
/// 0553A §4.5): the handlers' code in SRAM read-only and executable at
/// 0x2000_0000 and in its alias at 0, from `__sramcode` to `__eramcode`;
/// the RAM after it, where the image keeps its data, ring and stack,
/// writable.
pub fn mpu(r: &mut Report, m: &mut Machine) {
    let sym = |m: &Machine, s: &str| m.image.symbols.get(s).copied();
    let (Some(start), Some(end)) = (sym(m, "__sramcode"), sym(m, "__eramcode")) else {
        r.line(false, "mpu", "the image has no __sramcode/__eramcode: no code in SRAM to protect");
        return;
    };
    let mpu = &m.chip().nvic.mpu;
    let sram = 0x2000_0000;
    let code = |a: u32| {
        let x = mpu.access(a);
        x.read && !x.write && x.fetch
    };
    let unguarded: Vec<String> = (start..end)
        .step_by(64)
        .chain([end - 2])
        .filter(|&a| !code(a) || !code(sram + a))
        .map(|a| format!("{a:#x}"))
        .collect();
    let ram = polyturn_firmware::ramcode::RAMCODE_SIZE;
    let data_ok = [sram + ram, 0x2001_FFFC].iter().all(|&a| mpu.access(a).write);
    let ok = unguarded.is_empty() && data_ok;
    let text = format!(
        "the handlers' code {start:#x}..{end:#x} (and at {:#x}) read-only, executable: {}; RAM from {:#x} writable: {data_ok}",
        sram + start,
        if unguarded.is_empty() { "yes".to_string() } else { format!("not at {}", unguarded.join(", ")) },
        sram + ram
    );
    r.line(ok, "mpu", &text);
}

/// TIM3's and TIM5's words of `edgetime::program::CONFIG` as the timers hold
/// them after boot (CR1 and SR left out: DIR and the flags move by
/// themselves).
fn edge_time_words(m: &mut Machine) -> Vec<String> {
    use polyturn_firmware::edgetime::{off, program::Op, program::CONFIG, TIM3, TIM5};
    let c = m.chip();
    let mut bad = Vec::new();
    for op in CONFIG {
        let Op::Write(a, want) = op else { continue };
        let (i, base) = if a >= TIM5 { (2, TIM5) } else { (0, TIM3) };
        if [off::CR1, off::SR].contains(&(a - base)) {
            continue;
        }
        let got = c.gp[i].get(a - base);
        if got != want {
            bad.push(format!("{} +{:#x}: {got:#x}, edgetime::program {want:#x}", crate::chip::GP_NAMES[i], a - base));
        }
    }
    bad
}

/// Tick handler runs, TIM11 updates and UIF clears over a window.
pub struct TickWindow {
    pub t: (u64, u64),
    pub runs: (u64, u64),
    pub updates: (u64, u64),
    pub clears: (u64, u64),
}

pub fn tick_sample(m: &mut Machine) -> (u64, u64, u64, u64) {
    let c = m.chip();
    (
        c.now,
        c.entries.get(&crate::chip::probe::tick_exc()).copied().unwrap_or(0),
        c.mcu.tim11_updates(),
        c.probe.tick_uif_clears,
    )
}

pub fn tick(r: &mut Report, m: &mut Machine, w: &TickWindow) {
    let rate = tick_rate(m);
    let secs = (w.t.1 - w.t.0) as f64 / m.chip().sysclk() as f64;
    let want = rate * secs;
    let (runs, updates, clears) = (w.runs.1 - w.runs.0, w.updates.1 - w.updates.0, w.clears.1 - w.clears.0);
    let ok = (runs as f64 - want).abs() <= TICK_TOLERANCE && runs == updates && clears >= runs;
    let text = format!("TIM11 at {rate:.1} Hz; over {:.1} ms: {runs} handler runs (expected {want:.1}), {updates} update events, UIF cleared in {clears} runs", secs * 1e3);
    r.line(ok, "tick", &text);
}

pub fn safety(r: &mut Report, m: &mut Machine, name: &str, after: Outputs) {
    let f = faults(m);
    let p = &m.chip().probe;
    let ok = p.exti_return.is_some_and(|o| o.safe_now()) && after.safe_all() && f == "none";
    let lat = match (p.exti_entered, p.edge_at) {
        (Some(h), Some(e)) => format!("{} cycles", h - e),
        _ => "-".into(),
    };
    let show = |o: Option<Outputs>| o.map_or("never ran".to_string(), |o| o.to_string());
    let text = format!(
        "before: {} | EXTI15_10 entered {lat} after the edge (the model's clock), at its return: {} | 2 ms later: {after}; faults: {f}",
        show(p.before),
        show(p.exti_return)
    );
    r.line(ok, name, &text);
}

/// Report only: the longest PRIMASK sections (see `machine/primask.rs`) and the longest
/// that hold off the tick (`tickmask.rs`).
pub fn primask(r: &mut Report, m: &mut Machine) {
    let mhz = m.chip().sysclk() as f64 / 1e6;
    let tm = &m.chip().tickmask;
    let (tick_longest, tick_ticking, tick_n) = (tm.longest, tm.ticking, tm.sections);
    let log = &m.chip().primask;
    let (longest, ticking, n) = (log.longest, log.ticking, log.sections);
    let part = |s: crate::sections::Section| {
        format!(
            "{} cycles, {} on the bound ({:.1} us) from {} ({:#010x})",
            s.cycles,
            s.bound,
            s.bound as f64 / mhz,
            m.image.func_at(s.pc),
            s.pc
        )
    };
    let text = format!(
        "longest PRIMASK section in thread mode (holds off the E-stop): {}; with the tick running: {}; {n} sections. Longest holding off the tick (BASEPRI at its level, or PRIMASK): {}; with the tick running: {}; {} sections",
        part(longest),
        part(ticking),
        part(tick_longest),
        part(tick_ticking),
        tick_n
    );
    r.line(true, "irq-off", &text);
}
