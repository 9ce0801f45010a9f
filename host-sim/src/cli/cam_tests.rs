//! `cam`'s refusals of --rpm name a bound that is taken, and figures that
//! say what they compare.

use super::{run, CamArgs};
use clap::Parser;

#[derive(Parser)]
struct Line {
    #[command(flatten)]
    a: CamArgs,
}

fn cam(flags: &str) -> Result<String, String> {
    let a = Line::try_parse_from(format!("cam {flags}").split_whitespace()).map_err(|e| e.to_string())?.a;
    run(a).map_err(|e| e.0)
}

/// The bound in "--rpm must be <= X rpm ...".
fn named_bound(e: &str) -> String {
    let rest = e.strip_prefix("--rpm must be <= ").unwrap_or_else(|| panic!("{e}"));
    rest.split(' ').next().unwrap().to_string()
}

/// The two figures of "needs X ... A unit > L unit".
fn compared(e: &str) -> (String, String) {
    let (left, right) = e.split_once(" > ").unwrap_or_else(|| panic!("{e}"));
    let need = left.rsplit(' ').nth(1).unwrap().to_string();
    let limit = right.split(' ').next().unwrap().to_string();
    (need, limit)
}

#[test]
fn the_rpm_bound_named_is_taken_and_a_tenth_more_is_refused() {
    let cases = [
        "--sides 7 --inscribed-radius 20 --x-max-speed 3 --x-max-accel 70 --m 3",
        "--sides 8 --inscribed-radius 8 --x-max-speed 10 --x-max-accel 0.5",
        "--sides 3 --inscribed-radius 1 --x-max-speed 0.05 --x-max-accel 100",
    ];
    for case in cases {
        let e = cam(&format!("{case} --rpm 3000")).unwrap_err();
        let bound = named_bound(&e);
        assert!(cam(&format!("{case} --rpm {bound}")).is_ok(), "{case}: {e}");
        assert!(e.ends_with("(got 3000)"), "{e}");
        let over = format!("{:.1}", bound.parse::<f64>().unwrap() + 0.1);
        let refused = cam(&format!("{case} --rpm {over}")).unwrap_err();
        assert_eq!(named_bound(&refused), bound, "{refused}");
        assert!(refused.ends_with(&format!("(got {over})")), "{refused}");
        if refused.contains(" > ") {
            let (need, limit) = compared(&refused);
            assert_ne!(need, limit, "{refused}");
            assert!(need.parse::<f64>().unwrap() > limit.parse::<f64>().unwrap(), "{refused}");
        }
    }
}

#[test]
fn an_axis_too_slow_even_at_1_rpm_is_refused_with_the_need_at_1_rpm() {
    // X acceleration goes with the square of the speed: about 0.55 mm/s^2
    // at 1 rpm where 3000 rpm needs 4.9 million
    let e = cam("--sides 12 --inscribed-radius 50 --x-max-speed 1 --x-max-accel 0.2 --rpm 3000").unwrap_err();
    assert!(
        e.starts_with("--x-max-accel is too low: even a nearly round section at 1 rpm needs X acceleration 0."),
        "{e}"
    );
    let (need, limit) = compared(&e);
    assert!((0.5..0.6).contains(&need.parse::<f64>().unwrap()), "{e}");
    assert_eq!(limit, "0.2", "{e}");
    assert!(!e.contains("3000"), "{e}");
}
