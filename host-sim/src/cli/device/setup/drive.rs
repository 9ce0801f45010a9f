//! The guided setup's questions about a BLDC cutter: what the
//! board feeds the drive, the encoder the phase loop reads, the drive's
//! full speed and its time constant. A fact the board's rules refuse is
//! asked again, with the reason, a bounded number of times.

use super::super::prompt::{retry, Ask};
use crate::cli::errors::{CliError, CliResult};
use crate::cli::guided::bldc::{max_rate, BldcFacts};
use crate::cli::guided::GuidedArgs;
use polyturn_sync::config::bldc_out::check_pwm_hz;
use polyturn_sync::config::table::{BLDC_TAU, CUTTER_CPR, PWM_HZ};
use polyturn_sync::config::BldcOut;

/// The RC ESC's pulses, in the order offered.
const ESC: [(BldcOut, &str); 3] = [
    (BldcOut::Esc400, "400 Hz (most multirotor ESCs)"),
    (BldcOut::OneShot125, "OneShot125"),
    (BldcOut::Esc50, "50 Hz only (a servo-rate ESC: it cannot hold the cutter's phase)"),
];

/// The drive's facts; `esc`: an RC ESC, else a spindle driver's speed input.
pub fn facts(ask: &mut dyn Ask, a: &GuidedArgs, esc: bool) -> CliResult<BldcFacts> {
    let out = if esc {
        ESC[ask.choose("Which pulse does the ESC take?", &ESC.map(|(_, what)| what))?].0
    } else {
        BldcOut::Pwm
    };
    let pwm_hz = if out == BldcOut::Pwm { Some(pwm_hz(ask, a)?) } else { None };
    let q = "The cutter's encoder on PB6/PB7: counts per cutter turn (4 x lines x belt)";
    let counts = ask.number(q, a.cutter_encoder_cpr.filter(|&n| n != 0), CUTTER_CPR.lo, CUTTER_CPR.hi)?;
    let max_rate = retry(ask, |ask| {
        let q = "The cutter's speed at full command (100 % duty, or the ESC's 2.0 ms pulse), rpm";
        max_rate(ask.number(q, a.bldc.cutter_max_rpm, 1, 100_000)?, counts)
    })?;
    let q = "The drive's time constant, ms (the bench procedure, \"The BLDC drive\"; 0 if not measured yet)";
    let tau = ask.number(q, Some(a.bldc.bldc_tau.unwrap_or(0)), 0, BLDC_TAU.hi)?;
    Ok(BldcFacts { out, pwm_hz, tau_ms: (tau != 0).then_some(tau), counts, max_rate })
}

/// A frequency the timer makes exactly (`pwm-hz`'s rule).
fn pwm_hz(ask: &mut dyn Ask, a: &GuidedArgs) -> CliResult<u32> {
    retry(ask, |ask| {
        let hz =
            ask.number("The PWM frequency the driver takes, Hz", a.bldc.pwm_hz.or(Some(1_000)), PWM_HZ.lo, PWM_HZ.hi)?;
        check_pwm_hz(hz).map(|()| hz).map_err(|e| CliError(format!("pwm-hz {hz}: {}", e.allowed)))
    })
}
