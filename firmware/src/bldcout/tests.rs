use super::*;

/// The default full scale: max-rate 200 kHz, Q16 counts a tick.
const MAX: i64 = (200_000 << 16) / crate::board::TICK_HZ as i64;

fn out(name: &str) -> Out {
    Out::new(&Config::default().with("bldc-out", name).unwrap(), MAX)
}

#[test]
fn an_rc_esc_gets_1000_to_2000_us_and_never_beyond() {
    for name in ["esc50", "esc400"] {
        let o = out(name);
        assert_eq!((o.psc, o.stop, o.span), (95, 1_000, 1_000), "1 MHz counts");
        assert_eq!(o.ccr(0), 1_000);
        assert_eq!(o.ccr(MAX as u32 / 2), 1_500);
        assert_eq!(o.ccr(MAX as u32), 2_000);
        assert_eq!(o.ccr(u32::MAX), 2_000, "past full scale");
    }
    assert_eq!((out("esc50").arr, out("esc400").arr), (19_999, 2_499), "20 ms and 2.5 ms");
}

#[test]
fn oneshot125_is_125_to_250_us_every_500_us() {
    let o = out("oneshot125");
    assert_eq!((o.psc, o.arr), (1, 23_999), "48 MHz counts, 500 µs");
    assert_eq!((o.ccr(0), o.ccr(MAX as u32 / 2), o.ccr(MAX as u32)), (6_000, 9_000, 12_000));
}

#[test]
fn a_pwm_is_duty_0_to_100_percent_at_pwm_hz() {
    let o = out("pwm"); // 1 kHz: 48 MHz counts, 48 000 a period
    assert_eq!((o.psc, o.arr, o.stop), (1, 47_999, 0));
    assert_eq!((o.ccr(MAX as u32 / 4), o.ccr(MAX as u32)), (12_000, 48_000), "CCR1 > ARR: high throughout");
    let c = Config::default().with("bldc-out", "pwm").unwrap().with("pwm-hz", "20000").unwrap();
    let o = Out::new(&c, MAX);
    assert_eq!((o.psc, o.arr, o.ccr(MAX as u32)), (0, 4_799, 4_800));
}

#[test]
fn the_scale_rounds_so_full_speed_is_full_scale_for_any_max_rate() {
    for max in [1, 2, 3, 7, 1_000, 65_537, 524_287, 655_360, 4_000_000] {
        for name in ["esc50", "oneshot125", "pwm"] {
            let o = Out::new(&Config::default().with("bldc-out", name).unwrap(), max);
            assert_eq!(o.ccr(max as u32), o.stop + o.span, "{name} at {max}");
            assert_eq!(o.ccr(0), o.stop);
            // monotonic and within one count of the exact line
            let half = (max / 2) as u32;
            let exact = o.span as u64 * half as u64 / max as u64;
            assert!((o.ccr(half) - o.stop) as u64 - exact <= 1, "{name} at {max}");
        }
    }
}

#[test]
fn anything_but_a_running_drive_the_wired_way_gets_the_stop() {
    let o = out("esc50");
    let half = (MAX / 2) as i32;
    assert_eq!(o.command(true, half, true), 1_500);
    assert_eq!(o.command(false, half, true), 1_000, "halted, disabled, another drive");
    // dir same: forward is positive; dir opposite: negative
    assert_eq!(o.command(true, -half, true), 1_000);
    assert_eq!(o.command(true, -half, false), 1_500);
    assert_eq!(o.command(true, half, false), 1_000);
    assert_eq!(o.command(true, 0, true), 1_000);
    assert_eq!(out("pwm").command(true, -half, true), 0, "a PWM's stop is no pulse");
}

#[test]
fn a_new_scale_alone_keeps_the_frame() {
    let c = Config::default();
    assert!(Out::new(&c, MAX).same_frame(&Out::new(&c, MAX / 2)));
    assert_ne!(Out::new(&c, MAX), Out::new(&c, MAX / 2));
    assert!(!out("esc50").same_frame(&out("esc400")));
    let pwm2k = Config::default().with("bldc-out", "pwm").unwrap().with("pwm-hz", "2000").unwrap();
    // the same frame as OneShot125's, counted at another PSC
    assert!(!Out::new(&pwm2k, MAX).same_frame(&out("oneshot125")));
    assert_ne!(Out::new(&pwm2k, MAX).psc, out("oneshot125").psc);
}
