//! The guided setup of a BLDC cutter (`drive bldc`): the drive's facts as
//! flags (the interview asks the same), the settings they make, and what
//! the chosen `bldc-out` can hold, as the simulator measures it on the
//! drive behind each (`tests/bldc_drives.rs` pins the figures, the book's
//! performance page shows them).

use crate::cli::errors::{CliError, CliResult};
use crate::cli::values::{bldc_out, pwm_hz, setting, whole32};
use polyturn_sync::config::table::{BLDC_TAU, MAX_RATE};
use polyturn_sync::config::BldcOut;
use polyturn_sync::Config;

/// The BLDC's facts (with `--drive bldc`; its encoder is
/// `--cutter-encoder-cpr`).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct BldcArgs {
    /// With --drive bldc: what PB8 sends the drive: pwm (a spindle driver's speed input), esc400, oneshot125 or esc50 (an RC ESC's pulse) (the console's `bldc-out`)
    #[arg(long, value_name = "pwm|esc400|oneshot125|esc50", value_parser = bldc_out)]
    pub bldc_out: Option<BldcOut>,
    /// With --bldc-out pwm: the frequency the driver takes, Hz
    #[arg(long, value_name = "HZ", value_parser = pwm_hz)]
    pub pwm_hz: Option<u32>,
    /// With --drive bldc: the drive's time constant from the bench procedure, ms
    #[arg(long, value_name = "MS", value_parser = setting(BLDC_TAU))]
    pub bldc_tau: Option<u32>,
    /// With --drive bldc: the cutter's speed at full command (100 % duty, or the ESC's 2.0 ms pulse), rpm
    #[arg(long, value_name = "RPM", value_parser = whole32(1, 100_000))]
    pub cutter_max_rpm: Option<u32>,
}

/// What the setup sends for a BLDC cutter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BldcFacts {
    pub out: BldcOut,
    /// None: the board's `pwm-hz` stays (also for an ESC)
    pub pwm_hz: Option<u32>,
    /// None: not measured, the board's `bldc-tau` stays
    pub tau_ms: Option<u32>,
    /// the drive's encoder, counts per cutter turn (the console's `steps`)
    pub counts: u32,
    /// counts/s at full command (the console's `max-rate`)
    pub max_rate: u32,
}

/// The facts from the flags: the drive's encoder and full speed are
/// needed; a PWM frequency only with `pwm`.
pub fn from_flags(a: &BldcArgs, cutter_cpr: Option<u32>) -> CliResult<BldcFacts> {
    let need = |flag: &str| CliError::flag(flag, "is needed with --drive bldc");
    let out = a.bldc_out.ok_or_else(|| need("bldc-out"))?;
    let counts = cutter_cpr.filter(|&n| n != 0).ok_or_else(|| {
        CliError::flag(
            "cutter-encoder-cpr",
            "is needed with --drive bldc (4..=1000000: the encoder the phase loop reads on PB6/PB7)",
        )
    })?;
    let rpm = a.cutter_max_rpm.ok_or_else(|| need("cutter-max-rpm"))?;
    Ok(BldcFacts { out, pwm_hz: a.pwm_hz, tau_ms: a.bldc_tau, counts, max_rate: max_rate(rpm, counts)? })
}

/// `max-rate`, counts/s, from the cutter's full speed and its encoder.
pub fn max_rate(rpm: u32, counts: u32) -> CliResult<u32> {
    let rate = rpm as u64 * counts as u64 / 60;
    match u32::try_from(rate).ok().filter(|&r| MAX_RATE.contains(r)) {
        Some(r) => Ok(r),
        None => Err(CliError::flag(
            "cutter-max-rpm",
            format!(
                "x {counts} counts per turn / 60 is {rate} counts/s: the console's `max-rate` takes {} (got {rpm})",
                MAX_RATE.allowed
            ),
        )),
    }
}

/// The settings a BLDC cutter makes besides `steps` (its encoder's
/// counts, `Facts::steps`): `max-rate` the drive's full scale, and
/// `ferror` twice the error the drive is expected to reach in the cut (so
/// a good cut never trips it). A stepper's settings that would still act
/// on it or bind it go back to their defaults: `start-rate` (the follower
/// would jump the BLDC's speed, and it must not exceed `max-rate`) and
/// `pulse` (a STEP pulse bounds `max-rate`: max-rate x 2 x pulse <= 1 s).
pub fn changes(f: &BldcFacts) -> Vec<(String, String)> {
    let stepper = Config::default();
    let mut c = vec![
        ("drive".to_string(), "bldc".to_string()),
        ("bldc-out".into(), f.out.name().into()),
        ("max-rate".into(), f.max_rate.to_string()),
        ("ferror".into(), ferror(f.out, f.counts).to_string()),
        ("start-rate".into(), stepper.start_rate_hz.to_string()),
        ("pulse".into(), stepper.step_pulse_ns.to_string()),
    ];
    if let Some(hz) = f.pwm_hz {
        c.push(("pwm-hz".into(), hz.to_string()));
    }
    if let Some(ms) = f.tau_ms {
        c.push(("bldc-tau".into(), ms.to_string()));
    }
    c
}

/// The worst phase error while cutting the simulator measures through
/// each interface, millidegrees of the cutter (`tests/bldc_drives.rs`
/// checks every row against it: a spindle driver at 1 kHz with a 2, 20
/// or 100 ms loop and a 1 000- to 4 000-count encoder, an RC ESC at
/// 400 Hz and at 2 kHz); esc50 loses the phase.
pub fn expected_mdeg(out: BldcOut) -> Option<u32> {
    match out {
        BldcOut::Pwm => Some(700),
        BldcOut::Esc400 => Some(2_000),
        BldcOut::OneShot125 => Some(500),
        BldcOut::Esc50 => None,
    }
}

/// The least `ferror` for a BLDC cutter, counts: the phase loop reads its
/// encoder in whole counts, so a cutter within `e` counts of its target
/// reads up to `e + 1` behind; twice a promise under a count is less than
/// that, and 2 is not (a promise p <= 1 count reads at most p + 1 <= 2).
pub const FERROR_MIN_COUNTS: u32 = 2;

/// `ferror` for the drive: twice the error it is expected to reach
/// (`expected_mdeg`) in the encoder's counts, rounded up, and at least
/// `FERROR_MIN_COUNTS`; so a good cut never trips it, and a cutter that
/// falls behind by more does, on any encoder. An esc50 holds no phase:
/// nothing is promised, and the console's default stays.
pub fn ferror(out: BldcOut, counts: u32) -> u32 {
    let d = Config::default().following_error_limit_steps;
    expected_mdeg(out).map_or(d, |m| counts_of(2 * m, counts).max(FERROR_MIN_COUNTS))
}

/// `mdeg` millidegrees of the cutter in counts of its encoder, rounded up.
fn counts_of(mdeg: u32, counts: u32) -> u32 {
    (mdeg as u64 * counts as u64).div_ceil(360_000) as u32
}

/// `bldc-out esc50`: the one a machinist must not cut with.
pub const ESC50_WARNING: &str = "warning: bldc-out esc50: an RC ESC fed 50 times a second cannot hold the cutter's phase (in simulation the hexagon loses it as it synchronises): use esc400 or oneshot125 if the ESC takes them, or a spindle driver's speed input (bldc-out pwm)";

/// `bldc-tau` still at its default: the gains fit a drive nobody measured.
pub const TAU_UNMEASURED: &str = "bldc-tau is still the default 20 ms: measure the drive's (the bench procedure, \"The BLDC drive\") so the phase loop's gains fit it";

/// What the drive holds; `tau_given`: `bldc-tau` was set now, measured,
/// so its value is no default even where it equals one.
pub fn lines(c: &Config, tau_given: bool) -> Vec<String> {
    let mut out = vec![match c.bldc_out {
        BldcOut::Esc50 => ESC50_WARNING.to_string(),
        o => format!("{}; {}", what(o, c.pwm_hz), expect(o, c.motor_steps_per_rev)),
    }];
    if !tau_given && c.bldc_tau_ms == Config::default().bldc_tau_ms {
        out.push(TAU_UNMEASURED.to_string());
    }
    out
}

/// What the interface is and cannot do.
fn what(out: BldcOut, pwm_hz: u32) -> String {
    match out {
        BldcOut::Pwm => format!("bldc-out pwm at {pwm_hz} Hz (PB8, its sense on PB1): a spindle driver's speed loop"),
        o => format!(
            "bldc-out {}: an RC ESC has no speed loop and cannot brake: it needs max-accel within what the spindle coasts down by, and stops with a following error when the lathe stops faster than the cutter coasts",
            o.name()
        ),
    }
}

/// The accuracy to expect, in the cutter's degrees and the encoder's counts.
fn expect(out: BldcOut, counts: u32) -> String {
    let mdeg = expected_mdeg(out).unwrap_or(0);
    let section = match out {
        BldcOut::Pwm => "8 µm with a 2 ms speed loop, 21 µm with 100 ms",
        BldcOut::OneShot125 => "15 µm",
        _ => "49 µm",
    };
    format!(
        "expect the cutter within about {}.{}° while cutting ({} counts of its {counts}; in simulation the hexagon's section within {section}), so ferror {} counts",
        mdeg / 1000,
        mdeg % 1000 / 100,
        counts_of(mdeg, counts),
        ferror(out, counts)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(out: &str, tau: &str) -> Config {
        Config::default().with("drive", "bldc").unwrap().with("bldc-out", out).unwrap().with("bldc-tau", tau).unwrap()
    }

    #[test]
    fn esc50_is_a_warning_and_the_others_say_what_they_hold() {
        assert_eq!(lines(&with("esc50", "79"), false), [ESC50_WARNING]);
        let pwm = &lines(&with("pwm", "2"), false)[0];
        assert!(pwm.contains("at 1000 Hz") && !pwm.contains("warning"), "{pwm}");
        // 0.7° of the default 3 200 counts: 6.2, so 7 counts; ferror 2 x
        // 0.7° is 12.4, so 13 counts
        assert!(
            pwm.contains("within about 0.7° while cutting (7 counts of its 3200") && pwm.ends_with("ferror 13 counts"),
            "{pwm}"
        );
        for out in ["esc400", "oneshot125"] {
            let l = lines(&with(out, "79"), false);
            assert!(l[0].contains(out) && l[0].contains("cannot brake"), "{l:?}");
        }
        // 2° of 3 200 counts is 17.8; twice it 35.6, so 36
        let esc = &lines(&with("esc400", "79"), false)[0];
        assert!(esc.contains("2.0° while cutting (18 counts") && esc.ends_with("ferror 36 counts"), "{esc}");
    }

    #[test]
    fn the_facts_need_the_encoder_and_full_speed_and_make_max_rate_and_ferror() {
        let a = BldcArgs { bldc_out: Some(BldcOut::Esc400), cutter_max_rpm: Some(3_000), ..BldcArgs::default() };
        let f = from_flags(&a, Some(4_000)).unwrap();
        assert_eq!((f.counts, f.max_rate), (4_000, 200_000), "3 000 rpm x 4 000 counts / 60");
        assert!(changes(&f).contains(&("ferror".into(), "45".into())), "2 x 2° of 4 000 counts: {:?}", changes(&f));
        // a fine encoder: 2 x 2° of 100 000 counts
        let fine = from_flags(&BldcArgs { cutter_max_rpm: Some(100), ..a.clone() }, Some(100_000)).unwrap();
        assert!(changes(&fine).contains(&("ferror".into(), "1112".into())), "{:?}", changes(&fine));
        assert!(from_flags(&a, Some(0)).unwrap_err().0.starts_with("--cutter-encoder-cpr is needed"));
        assert!(from_flags(&a, None).is_err());
        let fast = BldcArgs { cutter_max_rpm: Some(4_000), ..a.clone() };
        let e = from_flags(&fast, Some(4_000)).unwrap_err().0;
        assert!(e.starts_with("--cutter-max-rpm") && e.contains("266666 counts/s"), "{e}");
        assert!(from_flags(&BldcArgs { bldc_out: None, ..a }, Some(4_000))
            .unwrap_err()
            .0
            .starts_with("--bldc-out is needed"));
    }

    /// Twice the accuracy the setup promises, in the encoder's counts: on a
    /// coarse encoder the fault stays reachable (2 counts, the least a
    /// reading in whole counts allows), on a fine one it is no looser
    /// than promised.
    #[test]
    fn ferror_is_twice_the_promised_accuracy_on_any_encoder() {
        // 2 x 0.7° of 4 000 counts is 15.6; 2 x 2° of 4 000, 44.4
        assert_eq!(ferror(BldcOut::Pwm, 4_000), 16);
        assert_eq!(ferror(BldcOut::Esc400, 4_000), 45);
        assert_eq!(ferror(BldcOut::OneShot125, 3_200), 9, "2 x 0.5° of 3 200 counts is 8.9");
        // 4 counts a turn: 2 x 2° is 0.04 count; a reading is up to a count
        // off, so 2 counts (half a turn), not 64 (16 turns)
        for out in [BldcOut::Pwm, BldcOut::Esc400, BldcOut::OneShot125] {
            assert_eq!(ferror(out, 4), 2, "{out:?}");
        }
        // 2 x 0.5° of 720 counts is exactly 2
        assert_eq!(ferror(BldcOut::OneShot125, 720), 2);
        assert_eq!(ferror(BldcOut::OneShot125, 721), 3);
        // esc50 holds no phase: nothing promised, the console's default
        assert_eq!(ferror(BldcOut::Esc50, 4_000), Config::default().following_error_limit_steps);
    }

    #[test]
    fn an_unmeasured_time_constant_is_pointed_out() {
        assert_eq!(lines(&with("pwm", "20"), false).last().unwrap(), TAU_UNMEASURED);
        assert_eq!(lines(&with("pwm", "19"), false).len(), 1);
    }
}
