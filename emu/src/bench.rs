//! `polyturn-emu --bench ELF`: a bare-metal benchmark image (not the board's
//! firmware: no jobs, no board checks) run from reset on the emulated chip, its
//! timed part measured on both clocks (`clock`: the model's and the bound's).
//!
//! The image's side (its symbols):
//! - `bench_start`, `bench_stop`: functions it calls right before and right
//!   after the timed part; each clock is read at their first instruction;
//! - `bench_done`: a function it calls at the end; the run stops there;
//! - `bench_iterations`: a `u32`, the timed part's iterations;
//! - `bench_ticks` (optional): a `u32`, the image's own count of the timed
//!   part (DWT_CYCCNT, which runs on the model's clock), printed beside it;
//! - `bench_log`, `bench_log_len` (optional): a byte array and a `u32`, the
//!   text it wrote, printed after the figures.
//!
//! CoreMark/MHz is iterations per second per MHz: iterations · 10⁶ / cycles
//! (EEMBC's CoreMark README, "Reporting rules": N iterations per second,
//! "CoreMark/MHz" when scaled by the clock).

use crate::clock::profile::Profile;
use crate::image::Image;
use crate::machine::Machine;
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

/// The run stops here if `bench_done` was not reached: 100 s at 96 MHz.
pub const CAP_CYCLES: u64 = 9_600_000_000;
/// `--cap-cycles`'s range.
const CAP_RANGE: std::ops::RangeInclusive<u64> = 1_000..=1_000_000_000_000;
/// Cycles per `Machine::run` between looks at the done mark.
const CHUNK: u64 = 10_000_000;

/// Both clocks at an instant: (model, bound) cycles.
pub type Clocks = (u64, u64);

/// What the hooks saw.
#[derive(Default)]
struct Marks {
    start: Option<Clocks>,
    stop: Option<Clocks>,
    done: bool,
    profile: Option<Profile>,
    /// times each block (address, size) ran between the marks (`profile`)
    runs: HashMap<(u32, u32), u64>,
}

/// A finished run's figures.
#[derive(Debug)]
pub struct Outcome {
    pub iterations: u32,
    pub start: Clocks,
    pub stop: Clocks,
    /// the image's own count of the timed part, if it kept one
    pub ticks: Option<u32>,
    /// FLASH_ACR as the image left it
    pub acr: u32,
    /// flash misses (instruction, literal) of the model and of the bound,
    /// over the whole run
    pub misses: [(u64, u64); 2],
    pub log: String,
    /// where the model's and the bound's cycles went between the marks, and
    /// the instructions run there, by function (with `profile`)
    pub profile: Vec<Row>,
}

/// A function's share of the timed part.
#[derive(Clone, Debug, Default)]
pub struct Row {
    pub function: String,
    pub model: u64,
    pub bound: u64,
    pub insns: u64,
}

impl Outcome {
    /// The timed part's cycles on each clock.
    pub fn cycles(&self) -> Clocks {
        (self.stop.0 - self.start.0, self.stop.1 - self.start.1)
    }
}

/// CoreMark/MHz in thousandths, rounded down: iterations · 10⁹ / cycles.
pub fn per_mhz_milli(iterations: u32, cycles: u64) -> u64 {
    (iterations as u128 * 1_000_000_000 / cycles.max(1) as u128) as u64
}

/// A function's address by its exact name.
fn function(image: &Image, name: &str) -> Result<u32, String> {
    image.symbols.get(name).map(|a| a & !1).ok_or_else(|| {
        format!("the image has no symbol `{name}`: not a bench image (bench_start, bench_stop, bench_done, bench_iterations)")
    })
}

/// Hooks `bench_start`, `bench_stop` and `bench_done`: each records both
/// clocks at its first instruction (the block's start plus the cycles to
/// it); the start begins a profile when asked for, the stop ends it.
fn hook_marks(m: &mut Machine, marks: &Rc<RefCell<Marks>>, profile: bool) -> Result<(), String> {
    let img = m.image.clone();
    let at = [function(&img, "bench_start")?, function(&img, "bench_stop")?, function(&img, "bench_done")?];
    for (which, addr) in at.into_iter().enumerate() {
        let marks = marks.clone();
        let hook = move |uc: &mut unicorn_engine::Unicorn<crate::chip::Chip>, _: u64, _: u32| {
            let c = uc.get_data_mut();
            let off = c.meter.offset(c.block, addr);
            let t = (c.blk + off.model as u64, c.blk_bound + off.bound as u64);
            let mut k = marks.borrow_mut();
            match which {
                0 if k.start.is_none() => {
                    k.start = Some(t);
                    c.profile = profile.then(Profile::default);
                }
                1 if k.start.is_some() && k.stop.is_none() => {
                    k.stop = Some(t);
                    k.profile = c.profile.take();
                }
                2 => k.done = true,
                _ => {}
            }
        };
        m.uc.add_code_hook(addr as u64, addr as u64, hook).map_err(|e| format!("unicorn: {e:?}"))?;
    }
    if profile {
        let marks = marks.clone();
        let count = move |_: &mut unicorn_engine::Unicorn<crate::chip::Chip>, addr: u64, size: u32| {
            let mut k = marks.borrow_mut();
            if k.start.is_some() && k.stop.is_none() {
                *k.runs.entry((addr as u32, size)).or_default() += 1;
            }
        };
        m.uc.add_block_hook(1, 0, count).map_err(|e| format!("unicorn: {e:?}"))?;
    }
    Ok(())
}

/// The profile by function: both clocks' cycles and the instructions run.
fn rows(image: &Image, profile: Option<Profile>, runs: &HashMap<(u32, u32), u64>) -> Vec<Row> {
    let Some(p) = profile else { return Vec::new() };
    let mut by: HashMap<String, Row> = HashMap::new();
    for (function, model, bound) in p.functions(0, |a| image.func_at(a)) {
        by.insert(function.clone(), Row { function, model, bound, insns: 0 });
    }
    for (&(addr, size), &n) in runs {
        let f = image.func_at(addr);
        by.entry(f.clone()).or_insert_with(|| Row { function: f, ..Row::default() }).insns +=
            n * image.program.block(addr, size).len() as u64;
    }
    let mut v: Vec<Row> = by.into_values().collect();
    v.sort_by_key(|r| std::cmp::Reverse(r.model));
    v
}

/// Runs the image from reset until `bench_done` or `cap` cycles (model).
pub fn run(image: &Rc<Image>, cap: u64, profile: bool) -> Result<Outcome, String> {
    let mut m = Machine::bare(image.clone())?;
    let marks = Rc::new(RefCell::new(Marks::default()));
    hook_marks(&mut m, &marks, profile)?;
    while !marks.borrow().done && m.chip().now < cap && m.chip().faults.is_empty() {
        let left = cap - m.chip().now;
        m.run(left.min(CHUNK));
    }
    if let Some((at, f)) = m.chip().faults.first() {
        return Err(format!("the image faulted at cycle {at}: {f}"));
    }
    let k = marks.take();
    let (Some(start), Some(stop), true) = (k.start, k.stop, k.done) else {
        let seen = [("bench_start", k.start.is_some()), ("bench_stop", k.stop.is_some()), ("bench_done", k.done)];
        let missing: Vec<&str> = seen.iter().filter(|s| !s.1).map(|s| s.0).collect();
        return Err(format!("{} not reached within {cap} cycles (--cap-cycles)", missing.join(", ")));
    };
    let iterations = read_u32(&m, "bench_iterations")?;
    if iterations == 0 {
        return Err("bench_iterations is 0: no iteration to divide by".into());
    }
    let profile = rows(image, k.profile, &k.runs);
    let (acr, misses) = (m.chip().flash_regs.get(0), m.chip().meter.misses());
    let ticks = read_u32(&m, "bench_ticks").ok();
    Ok(Outcome { iterations, start, stop, ticks, acr, misses, log: log(&m), profile })
}

fn read_u32(m: &Machine, name: &str) -> Result<u32, String> {
    let addr = *m.image.symbols.get(name).ok_or_else(|| format!("the image has no symbol `{name}`"))?;
    let mut w = [0u8; 4];
    m.uc.mem_read(addr as u64, &mut w).map_err(|e| format!("`{name}` at {addr:#010x}: {e:?}"))?;
    Ok(u32::from_le_bytes(w))
}

/// The image's `bench_log`, as long as `bench_log_len` says (and no longer
/// than 64 KiB); empty if it has none.
fn log(m: &Machine) -> String {
    let (Some(&addr), Ok(len)) = (m.image.symbols.get("bench_log"), read_u32(m, "bench_log_len")) else {
        return String::new();
    };
    let mut bytes = vec![0u8; len.min(65_536) as usize];
    match m.uc.mem_read(addr as u64, &mut bytes) {
        Ok(()) => String::from_utf8_lossy(&bytes).into_owned(),
        Err(e) => format!("(bench_log at {addr:#010x} unreadable: {e:?})"),
    }
}

/// The figures as printed: one line per clock.
pub fn report(o: &Outcome) -> String {
    let (model, bound) = o.cycles();
    let zero = std::env::var_os("POLYTURN_EMU_ZERO_WAIT").is_some();
    let mut s = format!(
        "FLASH_ACR {:#06x} (LATENCY {}{}); {} iterations between bench_start and bench_stop\n",
        o.acr,
        o.acr & 0xF,
        if zero { ", taken as 0: POLYTURN_EMU_ZERO_WAIT" } else { "" },
        o.iterations
    );
    s += "  clock   cycles          cycles/iteration  CoreMark/MHz\n";
    for (name, c) in [("model", model), ("bound", bound)] {
        let per = c as f64 / o.iterations as f64;
        let mhz = per_mhz_milli(o.iterations, c);
        s += &format!("  {name:<6}  {c:<14}  {per:<16.1}  {}.{:03}\n", mhz / 1000, mhz % 1000);
    }
    if let Some(t) = o.ticks {
        s += &format!("  the image's own count (bench_ticks, DWT_CYCCNT): {t}\n");
    }
    let [(mi, ml), (bi, bl)] = o.misses;
    s += &format!("  flash misses in the run (instruction, literal): model {mi}, {ml}; bound {bi}, {bl}\n");
    s
}

/// The profile's top functions, by the model's cycles, per iteration, with
/// cycles per instruction on each clock.
pub fn profile_table(o: &Outcome, top: usize) -> String {
    let ((model, _), n) = (o.cycles(), o.iterations as f64);
    let mut s = String::from(
        "  timed part by function, per iteration: model, bound cycles, instructions, CPI model / bound, model share\n",
    );
    let all = o.profile.iter().fold(Row { function: "(all)".into(), ..Row::default() }, |a, r| Row {
        model: a.model + r.model,
        bound: a.bound + r.bound,
        insns: a.insns + r.insns,
        ..a
    });
    for r in o.profile.iter().take(top).chain([&all]) {
        let cpi = |c: u64| c as f64 / r.insns.max(1) as f64;
        s += &format!(
            "    {:>10.1} {:>10.1} {:>10.1}  {:.2} / {:.2}  {:>5.1}%  {}\n",
            r.model as f64 / n,
            r.bound as f64 / n,
            r.insns as f64 / n,
            cpi(r.model),
            cpi(r.bound),
            100.0 * r.model as f64 / model.max(1) as f64,
            r.function
        );
    }
    s
}

/// `--bench`'s command line: `--cap-cycles=N`, `--profile`. Returns the exit
/// code: 0 with the figures, 2 if the image cannot run or reach its marks.
pub fn cli(image: &Rc<Image>, args: &[String]) -> i32 {
    let cap = match args.iter().find_map(|a| a.strip_prefix("--cap-cycles=")) {
        None => CAP_CYCLES,
        Some(v) => match v.parse::<u64>() {
            Ok(n) if CAP_RANGE.contains(&n) => n,
            _ => {
                eprintln!(
                    "emu: --cap-cycles: a whole number of CPU cycles, {}..={}",
                    CAP_RANGE.start(),
                    CAP_RANGE.end()
                );
                return 2;
            }
        },
    };
    let profile = args.iter().any(|a| a == "--profile");
    match run(image, cap, profile) {
        Ok(o) => {
            print!("{}", report(&o));
            if profile {
                print!("{}", profile_table(&o, 20));
            }
            if !o.log.is_empty() {
                println!("--- the image's log ---\n{}", o.log.trim_end());
            }
            0
        }
        Err(e) => {
            eprintln!("emu: --bench: {e}");
            2
        }
    }
}

#[cfg(test)]
mod tests;
