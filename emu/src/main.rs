//! polyturn's firmware image on an emulated STM32F411 (`bash .ci/emu`).
//!
//! usage: polyturn-emu ELF [-v] [--only=usb | --only=jobs | --job=NAME | --part=1|2 | --pty [--lathe-rpm RPM]]
//!        polyturn-emu --bench ELF [--cap-cycles=N] [--profile]
//!
//! Scenarios (each from reset, flash erased, so default settings):
//! 1. boot and run 160 ms with the E-stop closed (PB14 driven low) and no drive
//!    alarm (PB15 floating, pulled up): boot, registers, tick; then the E-stop
//!    opens (PB14 floats, its pull-up takes it high).
//! 2. boot and run 60 ms, then the drive alarm pulls PB15 low.
//! 3. USB (`usb::scenario`): the emulated host enumerates the console, sends
//!    `status` and `set cpr 0` and reads the replies. `--only=usb` runs just this.
//! 4. the jobs (`jobs`): `--only=jobs` runs just these, `--job=c` just those
//!    whose name begins so; (k) `job::damaged`: a damaged image does not run.
//!
//! `--part=1` runs 1 to 3, the jobs outside the table and job b, `--part=2`
//! the rest of the job table: two processes that share the checks at about
//! equal wall time.
//!
//! `--pty` instead boots, enumerates and serves the console on a pseudo-terminal
//! whose path it prints (`usb::pty`); with `--lathe-rpm RPM` the lathe turns at
//! that speed from then on (the host simulator's motor, no ripple). The board
//! resets as the chip does (the image's SYSRESETREQ, the watchdog, or SIGUSR1
//! for the NRST button) and serves on the same pty; when the image jumps to
//! the ROM bootloader (`dfu`), which is not emulated, it exits 3, or 1 if STEP
//! or ENABLE was not safe when it asked for the reset before the jump.
//!
//! `--bench` instead runs a bare-metal benchmark image (not the firmware) and
//! prints its timed part's cycles on both clocks (`bench`).
//!
//! The peripherals are `polyturn-stm32-model`'s: the project's one reading of the
//! manual. Exits 1 if a check fails, 2 if the image cannot run (with why), 3
//! when `--pty`'s image left for the ROM bootloader with its outputs safe.

mod bench;
mod checks;
mod chip;
mod clock;
mod cycles;
mod disasm;
mod edge_times;
mod image;
mod job;
mod jobs;
mod machine;
mod sections;
mod svd;
mod tickmask;
mod usb;

use checks::Report;
use machine::Machine;
use polyturn_stm32_model::Params;
use std::rc::Rc;
use std::time::Instant;

pub const MS: u64 = 96_000; // instructions per ms at the board's 96 MHz
const GPIOB: usize = 1;
const GPIOC: usize = 2;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value_of = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1));
    let lathe_rpm = value_of("--lathe-rpm");
    let Some(elf) = args.iter().find(|a| !a.starts_with('-') && Some(*a) != lathe_rpm) else {
        eprintln!("usage: polyturn-emu ELF");
        std::process::exit(2);
    };
    // a model's "not modelled" panic becomes a fault of the run, reported once
    std::panic::set_hook(Box::new(|_| {}));
    let bench = args.iter().any(|a| a == "--bench");
    let load = if bench { image::load_bare } else { image::load };
    let image = match load(std::path::Path::new(elf)) {
        Ok(i) => Rc::new(i),
        Err(e) => {
            eprintln!("emu: {e}");
            std::process::exit(2);
        }
    };
    if bench {
        std::process::exit(bench::cli(&image, &args));
    }
    if args.iter().any(|a| a == "--pty") {
        let rpm = match lathe_rpm.map(|r| r.parse::<f64>()) {
            Some(Ok(r)) if r.is_finite() && r.abs() <= 3000.0 => Some(r),
            Some(_) => exit_with("--lathe-rpm: a speed in rpm, -3000..=3000"),
            None => None,
        };
        match usb::pty::serve(&image, rpm) {
            usb::pty::Stop::Bootloader { at_request } => std::process::exit(left_for_the_rom(at_request)),
            usb::pty::Stop::Failed(e) => exit_with(&e),
        }
    }
    let wall = Instant::now();
    let mut r = Report::default();
    let sel = Select::of(&args);
    let mut total = if sel.scenarios() { scenarios(&image, &mut r).unwrap_or_else(exit) } else { 0 };
    if sel.usb() {
        total += usb::scenario::run(&image, &mut r).unwrap_or_else(exit);
        total += job::save::run(&image, &mut r).unwrap_or_else(exit);
        total += job::selftest::run(&image, &mut r).unwrap_or_else(exit);
    }
    total += jobs::run_all(&image, &mut r, &|name| sel.table(name)).unwrap_or_else(exit);
    if sel.other("h bldc") {
        total += job::bldc::run(&image, &mut r).unwrap_or_else(exit);
    }
    if sel.other("k damaged") {
        total += job::damaged::run(&image, &mut r).unwrap_or_else(exit);
    }
    if sel.other("divide") {
        total += job::divide::run(&image, &mut r).unwrap_or_else(exit);
    }
    println!(
        "emulated {total} cycles ({:.1} ms of MCU time) in {:.1} s wall; {} check(s) failed",
        total as f64 / 96e3,
        wall.elapsed().as_secs_f64(),
        r.failed
    );
    std::process::exit(if r.failed == 0 { 0 } else { 1 });
}

/// Which checks a run makes: all by default; `--only=usb`, `--only=jobs`
/// and `--job=NAME` narrow them. `--part=1` and `--part=2` split them into
/// halves of about equal wall time, for two processes on two cores
/// (`.ci/emu`): the scenarios, the USB console, the jobs outside the table
/// and [`PART_ONE_JOBS`]; and the rest of the job table.
struct Select<'a> {
    only_usb: bool,
    only_jobs: bool,
    /// `--job=c`: just the jobs whose name begins so (implies --only=jobs)
    job: Option<&'a str>,
    part: Option<u8>,
}

/// The table's jobs `--part=1` runs, the others taking about as long as
/// its checks outside the table (measured: 92 s and 161 s of wall time
/// with the table all in part 2, 106 s and 129 s with job b in part 1).
const PART_ONE_JOBS: &[&str] = &["b 11/3"];

impl<'a> Select<'a> {
    fn of(args: &'a [String]) -> Self {
        let job = args.iter().find_map(|a| a.strip_prefix("--job="));
        let part = args.iter().find_map(|a| a.strip_prefix("--part=")).map(|p| match p {
            "1" => 1,
            "2" => 2,
            _ => exit_with("--part: 1 or 2 (half the checks each)"),
        });
        let only_jobs = job.is_some() || args.iter().any(|a| a == "--only=jobs");
        Select { only_usb: args.iter().any(|a| a == "--only=usb"), only_jobs, job, part }
    }

    fn scenarios(&self) -> bool {
        !self.only_usb && !self.only_jobs && self.part != Some(2)
    }

    fn usb(&self) -> bool {
        !self.only_jobs && self.part != Some(2)
    }

    /// A job of the table, by its name.
    fn table(&self, name: &str) -> bool {
        let part = if PART_ONE_JOBS.contains(&name) { 1 } else { 2 };
        !self.only_usb && self.part.is_none_or(|p| p == part) && name.starts_with(self.job.unwrap_or(""))
    }

    /// A job outside the table, by its name.
    fn other(&self, name: &str) -> bool {
        !self.only_usb && self.part != Some(2) && self.job.is_none_or(|j| name.starts_with(j))
    }
}

/// The image jumped to ST's ROM bootloader (`dfu`): exit 3 if, when it asked for
/// the reset before the jump, STEP (PA8) was low and ENABLE (PB13) inactive; else 1.
fn left_for_the_rom(at_request: Option<chip::pins::Outputs>) -> i32 {
    let safe = at_request.is_some_and(|o| o.step == Some(false) && o.enable == Some(o.enable_inactive));
    let how = at_request.map_or("no software reset before it".to_string(), |o| o.to_string());
    if safe {
        eprintln!("emu: the image jumped to the ROM bootloader (system memory); at its reset request STEP (PA8) was low and ENABLE (PB13) inactive ({how})");
        3
    } else {
        eprintln!("emu: FAILED: the image jumped to the ROM bootloader (system memory) with STEP (PA8) or ENABLE (PB13) not safe at its reset request ({how})");
        1
    }
}

fn exit_with(e: &str) -> ! {
    eprintln!("emu: {e}");
    std::process::exit(2);
}

fn exit(e: String) -> u64 {
    eprintln!("emu: {e}");
    std::process::exit(2);
}

fn boot(image: &Rc<Image>) -> Result<Machine, String> {
    let mut m = Machine::new(image.clone(), Params::default(), &[])?;
    m.drive(GPIOB, 14, Some(false)); // E-stop closed to GND
    Ok(m)
}

use image::Image;

fn scenarios(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    // 1: boot, registers, tick, E-stop
    let mut m = boot(image)?;
    m.run(60 * MS);
    let s0 = checks::tick_sample(&mut m);
    m.run(100 * MS);
    let s1 = checks::tick_sample(&mut m);
    let led = m.chip().gpio[GPIOC].output_since[13];
    checks::boot(r, &mut m, led);
    checks::registers(r, &mut m);
    checks::mpu(r, &mut m);
    let w = checks::TickWindow { t: (s0.0, s1.0), runs: (s0.1, s1.1), updates: (s0.2, s1.2), clears: (s0.3, s1.3) };
    checks::tick(r, &mut m, &w);
    m.chip().probe.trip = Some((GPIOB, 14, None)); // the contact opens: PB14 floats high
    m.run(2 * MS);
    let after = m.chip().outputs();
    checks::safety(r, &mut m, "safety-estop", after);
    checks::primask(r, &mut m);
    let mut total = m.chip().now;

    // 2: the drive alarm from a fresh boot
    let mut m = boot(image)?;
    m.run(60 * MS);
    m.chip().probe.trip = Some((GPIOB, 15, Some(false))); // the drive pulls ALARM to GND
    m.run(2 * MS);
    let after = m.chip().outputs();
    checks::safety(r, &mut m, "safety-alarm", after);
    total += m.chip().now;
    Ok(total)
}
