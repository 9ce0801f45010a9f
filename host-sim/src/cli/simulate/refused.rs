//! Why a simulation is refused, or failed: each names the flag whose
//! value is out of range, the figure and where it came from, and what it
//! got. A run that never cut is a failure, not a report.

use super::SimulateArgs;
use crate::cli::errors::CliError;
use crate::sim::bldc_drive::{full_speed, own_tau_ms, INERTIA_KG_M2};
use crate::sim::{Scenario, SimResult};
use polyturn_sync::config::table::BLDC_TAU;
use polyturn_sync::config::{BldcOut, Rule};
use polyturn_sync::{Config, ConfigError, DriveKind};

/// A run that cut fewer lathe turns than its pattern takes to cut every
/// side once: its section is not the polygon (whole sides uncut), so no
/// report of it is given.
pub fn cut_short(sc: &Scenario, r: &SimResult, a: &SimulateArgs) -> Option<CliError> {
    let (sides, turns) = sc.setup.pattern();
    (r.cut_turns < f64::from(turns)).then(|| {
        CliError(format!(
            "simulate: the cut is not whole: the cutter cut for {:.2} lathe turns, and {} x {} cuts its {sides} sides in {turns} (give --revolutions enough for {turns} turns of cutting after it synchronises; got {})",
            r.cut_turns, sc.setup.ratio, sc.setup.edges, a.revolutions
        ))
    })
}

/// A cut a latched fault stopped before every side was cut: said by that
/// fault, when, and the flag behind it; more --revolutions would not help.
pub fn stopped_by_fault(sc: &Scenario, r: &SimResult, a: &SimulateArgs) -> Option<CliError> {
    let &(tick, f) = r.faults.first()?;
    let (_, turns) = sc.setup.pattern();
    (r.cut_turns < f64::from(turns)).then(|| {
        CliError(format!(
            "simulate: the cut is not whole: the controller latched a {} fault at {:.2} s, {:.2} lathe turns into the cut, which stopped there: {}",
            f.name(),
            tick as f64 / sc.tick_hz as f64,
            r.cut_turns,
            fault_cause(sc, a, f)
        ))
    })
}

/// What made a fault while cutting, by the flag that set it: a ripple
/// past max-accel, a lathe encoder too coarse, or the BLDC's drive.
fn fault_cause(sc: &Scenario, a: &SimulateArgs, f: polyturn_sync::Fault) -> String {
    let need = sc.ripple_accel(a.rpm);
    let max = sc.core.max_accel_steps_per_s2 as f64;
    if need > max {
        return format!(
            "the lathe's speed ripple (--ripple {}) asks the cutter for up to {need:.0} steps/s², past its max-accel {max} (lower --ripple or --rpm, or raise --max-accel)",
            a.ripple
        );
    }
    if let Some(coarse) = coarse_encoder(sc) {
        return coarse;
    }
    match (sc.core.drive, sc.core.bldc_out) {
        (polyturn_sync::DriveKind::Bldc, BldcOut::Esc50) => "--bldc-out esc50: an RC ESC fed 50 times a second cannot hold the cutter's phase (use esc400 or oneshot125, or a spindle driver, --bldc-out pwm)".into(),
        (polyturn_sync::DriveKind::Bldc, out) if f == polyturn_sync::Fault::FollowingError => format!(
            "the cutter fell behind: its drive too slow for the lathe (--bldc-out {}, --bldc-tau {} ms)",
            out.name(),
            sc.core.bldc_tau_ms
        ),
        _ => f.reason().into(),
    }
}

/// The share of the depth of cut past which a section is no polygon of
/// this setup: its flats are further from the ideal than half the metal
/// the cutter was to take.
pub const MISSED_SHARE: f64 = 0.5;

/// A run that cut, but not the polygon: the section is as far from the
/// ideal as the cut is deep (the cutter out of phase by most of a flat).
/// Said as an error, with the phase error that made it, rather than a
/// report whose "faults: none" reads as a good cut.
pub fn missed(sc: &Scenario, r: &SimResult, a: &SimulateArgs) -> Option<CliError> {
    let depth = sc.setup.depth_mm;
    (r.max_profile_deviation > MISSED_SHARE * depth).then(|| {
        CliError(format!(
            "simulate: the polygon was not cut: the section is {:.0} µm from the ideal, {:.0} % of the {depth} mm depth of cut; the cutter's phase error while cutting reached {:.1} steps ({})",
            r.max_profile_deviation * 1000.0,
            r.max_profile_deviation / depth * 100.0,
            r.max_error_steps_cutting,
            missed_because(sc, a)
        ))
    })
}

/// What to change when the polygon was missed: a start rate past what
/// the simulated motor pulls in loses the steps of its jump, silently
/// (no fault: nothing counts them); else the speed the cutter follows.
fn missed_because(sc: &Scenario, a: &SimulateArgs) -> String {
    let pull_in = crate::sim::pull_in_hz(sc.motor_max_rate_hz, sc.motor_max_accel, 1.0 / sc.tick_hz as f64);
    let start = sc.core.start_rate_hz;
    match sc.core.drive {
        polyturn_sync::DriveKind::Bldc => {
            format!("lower --ripple or --rpm, or drive the cutter with a stepper; got --ripple {} at {} rpm", a.ripple, a.rpm)
        }
        _ if f64::from(start) > pull_in => format!(
            "--start-rate {start} is past what the simulated motor pulls in at once from rest, at most {:.0} steps/s: the jump to it lost steps; lower --start-rate",
            pull_in.floor()
        ),
        _ => format!("raise --motor-steps, or lower --ripple or --rpm; got --ripple {} at {} rpm", a.ripple, a.rpm),
    }
}

/// A run whose controller latched a fault failed, however well it cut: on
/// the board the cutter stopped there and waits for `clear`. Said with
/// which fault, when, and what the machinist can do.
pub fn latched(sc: &Scenario, r: &SimResult, a: &SimulateArgs) -> Option<CliError> {
    let &(tick, f) = r.faults.first()?;
    let at =
        format!("simulate: the controller latched a {} fault at {:.2} s", f.name(), tick as f64 / sc.tick_hz as f64);
    // the lathe stops once the cut is whole (`Scenario::standard`): a
    // fault after that came while it ran down
    if r.cut_turns < a.revolutions {
        return Some(CliError(format!(
            "{at}, {:.2} of the {} lathe turns into the cut, which stopped there ({})",
            r.cut_turns,
            a.revolutions,
            f.reason()
        )));
    }
    let stops = sc.lathe.legs.last().map_or(0.0, |l| l.accel_rpm_per_s);
    Some(CliError(format!(
        "{at}, after the cut was whole, while the lathe ran down from {} rpm at {stops} rpm/s: {}",
        a.rpm,
        run_down(sc, f)
    )))
}

/// Why a fault came in the lathe's run-down, and the way round it: the
/// cutter follows the lathe down only as fast as its drive slows it.
fn run_down(sc: &Scenario, f: polyturn_sync::Fault) -> String {
    const STOP_FIRST: &str = "stop the cutter (`stop` on the board) before stopping the lathe";
    if f != polyturn_sync::Fault::FollowingError {
        return f.reason().into();
    }
    match (sc.core.drive, sc.core.bldc_out) {
        (polyturn_sync::DriveKind::Bldc, BldcOut::Pwm) => format!(
            "the cutter fell behind: its drive (--bldc-tau {} ms) cannot slow it as fast as the lathe stops; {STOP_FIRST}, or use a faster spindle driver",
            sc.core.bldc_tau_ms
        ),
        (polyturn_sync::DriveKind::Bldc, out) => format!(
            "the cutter fell behind: an RC ESC ({}) cannot brake, so the cutter coasts down slower than the lathe stops; {STOP_FIRST}, or drive it with one that brakes (a spindle driver, --bldc-out pwm)",
            out.name()
        ),
        _ => format!(
            "the cutter fell behind: it cannot slow as fast as the lathe stops within its max-accel {} steps/s²; {STOP_FIRST}, or raise --max-accel",
            sc.core.max_accel_steps_per_s2
        ),
    }
}

/// A setting the simulated board refuses, named by the flag it came from
/// (the board's `max-rpm` is --rpm and 30 %: the ripple's headroom). `c`
/// is the board's settings as refused (with the BLDC's drive fitted).
pub fn setting(e: ConfigError, c: &Config, a: &SimulateArgs) -> CliError {
    match e.field {
        // the rules on max-rpm: --rpm is the flag that sets it
        "ratio" | "bldc-out" => too_fast(c, a.rpm),
        "cpr" => CliError::flag("encoder-cpr", format!("{} (got {})", e.allowed, c.encoder_counts_per_rev)),
        "steps" => CliError::flag("motor-steps", format!("{} (got {})", e.allowed, c.motor_steps_per_rev)),
        // (simulate has no max-rate flag: the figure is the simulated motor's)
        "start-rate" if c.start_rate_hz > c.max_step_rate_hz => CliError::flag(
            "start-rate",
            format!(
                "must not exceed the simulated board's max-rate, {} steps/s (got {})",
                c.max_step_rate_hz, c.start_rate_hz
            ),
        ),
        "start-rate" => CliError::flag("start-rate", format!("{} (got {})", e.allowed, c.start_rate_hz)),
        "pwm-hz" => CliError::flag("pwm-hz", format!("{} (got {})", e.allowed, c.pwm_hz)),
        "bldc-tau" => CliError::flag("bldc-tau", format!("{} (got {})", e.allowed, c.bldc_tau_ms)),
        f => CliError::flag(f, e.allowed),
    }
}

/// The rule on the board's max-rpm that binds it most tightly with the
/// others as in `c` (the step rate; with a BLDC, also its command rate),
/// and the largest max-rpm it allows.
fn tightest_max_rpm(c: &Config) -> (Rule, u64) {
    let bldc = c.drive == DriveKind::Bldc;
    [Rule::StepRate, Rule::CommandRate]
        .into_iter()
        .filter(|r| *r != Rule::CommandRate || bldc)
        .filter_map(|r| r.bound("max-rpm", c).map(|b| (r, b.num / b.den.max(1))))
        .min_by_key(|&(_, max)| max)
        .unwrap_or((Rule::StepRate, 0))
}

/// --rpm past what the board's rules allow: the fastest --rpm that all of
/// them take, from the rule that binds it most tightly and the 30 % the
/// simulated board's max-rpm adds to --rpm (`max_rpm_for`).
fn too_fast(c: &Config, rpm: f64) -> CliError {
    let (rule, max_rpm) = tightest_max_rpm(c);
    let ratio = c.ratio;
    let (why, from, otherwise) = match rule {
        Rule::CommandRate => (
            format!("ratio {ratio} with --bldc-out {}", c.bldc_out.name()),
            format!(
                "{} commands/s: the drive must take a command at least once per cutter revolution",
                c.bldc_out.frame_hz(c.pwm_hz)
            ),
            "give --bldc-out a drive that takes commands faster: oneshot125 or pwm",
        ),
        _ => (
            format!("ratio {ratio} at {} steps a turn", c.motor_steps_per_rev),
            format!("the board's max-rate {} steps/s", c.max_step_rate_hz),
            "lower --motor-steps",
        ),
    };
    match crate::sim::fastest_rpm_within(u32::try_from(max_rpm).unwrap_or(u32::MAX)) {
        Some(fastest) => {
            CliError::flag("rpm", format!("must be at most {fastest} rpm for {why} ({from}, with 30 % headroom) (got {rpm})"))
        }
        None => CliError::flag(
            "rpm",
            format!("cannot be met at any speed: {why} needs more than {from}, even at the simulated board's least max-rpm, 60 ({otherwise}) (got {rpm})"),
        ),
    }
}

/// The RC ESC's own time constant (inertia × full speed / stall torque,
/// the full speed `max-rate` counts/s of the cutter's encoder) when it is
/// out of `bldc-tau`'s range: a coarse encoder makes the full speed, and
/// with it the time constant, too large.
pub fn own_tau(sc: &Scenario, out: BldcOut, motor_steps: u32) -> Result<(), CliError> {
    let ms = own_tau_ms(sc, out);
    if BLDC_TAU.contains(ms) {
        return Ok(());
    }
    Err(CliError::flag(
        "motor-steps",
        format!(
            "makes the simulated ESC's own time constant {ms} ms (inertia {INERTIA_KG_M2} kg·m² x full speed {:.0} rad/s, max-rate {} counts/s over {motor_steps} counts a turn, / stall torque {} N·m), outside bldc-tau's {}: give --bldc-tau, or more counts a turn (got {motor_steps})",
            full_speed(sc),
            sc.core.max_step_rate_hz,
            sc.bldc_max_torque,
            BLDC_TAU.allowed
        ),
    ))
}

/// A run that never cut: why, as far as the figures tell.
pub fn nothing_cut(sc: &Scenario, r: &SimResult, a: &SimulateArgs) -> CliError {
    let mut why = vec![format!(
        "simulate: nothing was cut: the cutter never held the gear while the lathe held its {} rpm",
        a.rpm
    )];
    let need = sc.ripple_accel(a.rpm);
    let max = sc.core.max_accel_steps_per_s2 as f64;
    if need > max {
        // the ripple the follower holds here, rounded down: `ripple_accel` is linear in it
        let held = (sc.lathe.ripple * max / need * 1e3).floor() / 1e3;
        why.push(format!(
            "the lathe's speed ripple (--ripple {}: ±{:.0} % once a turn) asks the cutter for up to {need:.0} steps/s², past its max-accel {max}: the follower holds a ripple of at most about {held} here (lower --ripple or --rpm, or raise --max-accel)",
            a.ripple,
            a.ripple * 100.0
        ));
    }
    let coarse = coarse_encoder(sc);
    let reason = |f: polyturn_sync::Fault| match (&coarse, sc.core.drive) {
        (Some(_), _) => String::new(),
        (None, polyturn_sync::config::DriveKind::Bldc) if f == polyturn_sync::Fault::FollowingError => {
            " (the cutter fell behind: its drive too slow for the lathe, --bldc-out and --bldc-tau)".into()
        }
        (None, _) => format!(" ({})", f.reason()),
    };
    why.extend(coarse.clone());
    if let Some((tick, f)) = r.faults.first() {
        why.push(format!("{} at {:.2} s{}", f.name(), *tick as f64 / sc.tick_hz as f64, reason(*f)));
    }
    CliError(why.join("; "))
}

/// Of the following-error limit, what one lathe count may move the
/// cutter's target by and still be followed: the follower lags a count's
/// jump and the ramp to it (measured: 2 x 3 edges, 3 200 steps, `ferror`
/// 64, cuts from 123 counts a turn, 52 steps a count; 0.75 of 64 is 48).
const COUNT_OF_FERROR: f64 = 0.75;

/// A lathe encoder so coarse that each of its counts moves the cutter's
/// target by most of the following-error limit: the cutter can only lag
/// it, and no motor or max-accel helps. Named with a cpr that does.
fn coarse_encoder(sc: &Scenario) -> Option<String> {
    let c = &sc.core;
    let steps_a_turn = c.ratio.to_f64() * c.motor_steps_per_rev as f64;
    let per_count = steps_a_turn / c.encoder_counts_per_rev as f64;
    let limit = c.following_error_limit_steps as f64;
    (per_count > COUNT_OF_FERROR * limit).then(|| {
        let need = (steps_a_turn / (COUNT_OF_FERROR * limit)).ceil();
        format!(
            "each lathe count (--encoder-cpr {}) moves the cutter's target {per_count:.0} steps, more than the follower holds within its following-error limit of {limit} steps: a finer lathe encoder, {need} counts a turn or more",
            c.encoder_counts_per_rev
        )
    })
}

#[cfg(test)]
#[path = "refused_tests.rs"]
mod tests;
