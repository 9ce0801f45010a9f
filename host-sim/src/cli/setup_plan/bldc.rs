//! What `polyturn device setup` tells a machinist whose cutter is a BLDC
//! (`drive bldc`): what the chosen `bldc-out` can hold, as the simulator
//! measures it on the drive behind each (`tests/bldc_drives.rs`, the book's
//! performance page), and what to set or measure first.

use polyturn_sync::config::BldcOut;
use polyturn_sync::Config;

/// `bldc-out esc50`: the one a machinist must not cut with.
pub const ESC50_WARNING: &str = "warning: bldc-out esc50: an RC ESC fed 50 times a second cannot hold the cutter's phase (in simulation the hexagon loses it as it synchronises): use esc400 or oneshot125 if the ESC takes them, or a spindle driver's speed input (bldc-out pwm)";

/// `bldc-tau` still at its default: the gains fit a drive nobody measured.
pub const TAU_UNMEASURED: &str = "bldc-tau is still the default 20 ms: measure the drive's (the bench procedure, \"The BLDC drive\") so the phase loop's gains fit it";

pub fn lines(c: &Config) -> Vec<String> {
    let mut out = vec![match c.bldc_out {
        BldcOut::Pwm => format!(
            "bldc-out pwm at {} Hz (PB8, its sense on PB1): a spindle driver with a 2 ms speed loop holds the cutter within about 6 counts of its encoder while cutting (in simulation the hexagon's section is within 27 µm)",
            c.pwm_hz
        ),
        BldcOut::Esc400 | BldcOut::OneShot125 => format!(
            "bldc-out {}: an RC ESC has no speed loop and cannot brake: in simulation it holds the cutter within 28 to 58 counts while cutting (0.14 to 0.2 mm on the hexagon's section), needs max-accel within what the spindle coasts down by, and stops with a following error when the lathe stops faster than the cutter coasts",
            c.bldc_out.name()
        ),
        BldcOut::Esc50 => ESC50_WARNING.to_string(),
    }];
    if c.bldc_tau_ms == Config::default().bldc_tau_ms {
        out.push(TAU_UNMEASURED.to_string());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(out: &str, tau: &str) -> Config {
        Config::default().with("drive", "bldc").unwrap().with("bldc-out", out).unwrap().with("bldc-tau", tau).unwrap()
    }

    #[test]
    fn esc50_is_a_warning_and_the_others_say_what_they_hold() {
        assert_eq!(lines(&with("esc50", "79")), [ESC50_WARNING]);
        assert!(lines(&with("pwm", "2"))[0].contains("at 1000 Hz") && !lines(&with("pwm", "2"))[0].contains("warning"));
        for out in ["esc400", "oneshot125"] {
            let l = lines(&with(out, "79"));
            assert!(l[0].contains(out) && l[0].contains("cannot brake"), "{l:?}");
        }
    }

    #[test]
    fn an_unmeasured_time_constant_is_pointed_out() {
        assert_eq!(lines(&with("pwm", "20")).last().unwrap(), TAU_UNMEASURED);
        assert_eq!(lines(&with("pwm", "19")).len(), 1);
    }
}
