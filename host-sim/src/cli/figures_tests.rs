use super::*;

const REPLY: &str =
    "ok encoder ended moved=12000 backward=0 jumps=0 chatter=0 still=done indexes=4 skipped=0 gaps=3 gap=4000..4000 cpr=4000";

#[test]
fn the_boards_reply_is_read_field_by_field() {
    let f = parse_encoder(REPLY).unwrap();
    assert_eq!((f.moved, f.indexes, f.gap, f.cpr), (12_000, 4, Some((4_000, 4_000)), Some(4_000)));
    let none = parse_encoder(
        "ok encoder moved=-5 backward=1 jumps=0 chatter=3 still=measuring indexes=0 skipped=0 gaps=0 gap=none cpr=none",
    )
    .unwrap();
    assert_eq!((none.moved, none.gap, none.cpr), (-5, None, None));
    assert_eq!(parse_encoder("ok state=idle"), None);
    assert_eq!(parse_encoder("ok encoder moved=x"), None);
}

#[test]
fn a_cpr_is_proposed_from_the_index_or_from_counted_turns() {
    let f = parse_encoder(REPLY).unwrap();
    assert_eq!(propose_cpr(&f, None), Ok(4_000));
    // no index: 3 turns by hand, a count or two off
    let hand = EncoderFigures { moved: -7_202, cpr: None, gap: None, indexes: 0, ..f.clone() };
    assert_eq!(propose_cpr(&hand, Some(3)), Ok(2_400), "600 lines x 4, the mark 2 counts off");
    let nothing = EncoderFigures { moved: 1, ..hand.clone() };
    assert!(propose_cpr(&nothing, Some(3)).unwrap_err().contains("is the encoder connected"));
    assert!(propose_cpr(&hand, None).unwrap_err().contains("0 index pulse(s)"));
    let lost = EncoderFigures { cpr: None, gap: Some((3_990, 4_000)), ..f.clone() };
    assert!(propose_cpr(&lost, None).unwrap_err().contains("varied from 3990 to 4000"));
    let noisy = EncoderFigures { jumps: 2, ..f };
    assert!(propose_cpr(&noisy, None).unwrap_err().contains("2 jump(s)"));
}

#[test]
fn steps_per_cutter_turn_count_microsteps_and_pulleys() {
    assert_eq!(steps_per_cutter_turn(200, 16, (1, 1)), Ok(3_200));
    assert_eq!(steps_per_cutter_turn(200, 8, (40, 20)), Ok(3_200));
    assert_eq!(steps_per_cutter_turn(200, 1, (36, 20)), Ok(360));
    assert!(steps_per_cutter_turn(200, 1, (37, 21)).is_err());
}

#[test]
fn the_dir_setting_undoes_a_reversed_encoder_or_motor() {
    use Sense::*;
    assert_eq!(dir_setting(Same, false, false), Same);
    assert_eq!(dir_setting(Opposite, false, false), Opposite);
    assert_eq!(dir_setting(Same, true, false), Opposite);
    assert_eq!(dir_setting(Same, false, true), Opposite);
    assert_eq!(dir_setting(Same, true, true), Same, "two reversals cancel");
    assert_eq!(dir_setting(Opposite, true, false), Same);
}

#[test]
fn the_fastest_lathe_speed_is_the_motors_or_the_lathes_limit() {
    // 3200 steps, 200 kHz: 2:1 → 200000·60/(2·3200) = 1875 rpm, max-rpm 1500
    let c = Config::default();
    assert_eq!(fastest_lathe_rpm(&c, 2, 1), 1_500);
    assert_eq!(fastest_lathe_rpm(&c, 4, 1), 937);
    assert_eq!(fastest_lathe_rpm(&c, 5, 2), 1_500);
    assert_eq!(steps_per_count(&c), (8, 3), "2 x 3200 / 2400");
}

#[test]
fn settings_are_read_back_and_sent_in_an_order_the_board_accepts() {
    let c = Config::default();
    // the board's own `get` line
    let mut ctl =
        polyturn_sync::Controller::new(Config { encoder_counts_per_rev: 4_000, ..c }, polyturn_sync::Timing::FIRMWARE);
    let get = polyturn_sync::console::handle(b"get", &mut ctl).0.to_string();
    assert_eq!(parse_settings(&get).unwrap().encoder_counts_per_rev, 4_000);
    // 11/3 fits only once max-rpm, listed last, is down from the default's
    let slow = Config { max_lathe_rpm: 600, ratio: polyturn_sync::Ratio::parse("11/3").unwrap(), ..c };
    let mut ctl = polyturn_sync::Controller::new(slow, polyturn_sync::Timing::FIRMWARE);
    let get = polyturn_sync::console::handle(b"get", &mut ctl).0.to_string();
    assert_eq!(parse_settings(&get), Some(slow), "{get}");
    // more steps at the same max-rpm would overspeed until max-rpm drops:
    // 1500 rpm x 2 x 8000 / 60 = 400 kHz > 200 kHz
    let changes = vec![("steps".to_string(), "8000".to_string()), ("max-rpm".to_string(), "600".to_string())];
    let (order, end) = send_order(&c, &changes).unwrap();
    assert_eq!((end.motor_steps_per_rev, end.max_lathe_rpm), (8_000, 600));
    assert_eq!(order[0].0, "max-rpm", "{order:?}");
    let impossible = vec![("steps".to_string(), "80000".to_string())];
    assert!(send_order(&c, &impossible).unwrap_err().contains("do not fit together"));
}

#[test]
fn a_board_reporting_gaps_at_the_ends_of_the_range_gets_an_answer_not_a_panic() {
    let line = format!(
        "ok encoder ended moved=12000 backward=0 jumps=0 chatter=0 still=done indexes=4 skipped=0 gaps=3 gap={}..{} cpr=none",
        i64::MIN,
        i64::MAX
    );
    let f = parse_encoder(&line).unwrap();
    assert_eq!(f.gap, Some((i64::MIN, i64::MAX)));
    assert!(propose_cpr(&f, None).unwrap_err().contains("varied"));
}

#[test]
fn the_index_measurement_wins_over_counted_turns() {
    let f = parse_encoder(REPLY).unwrap();
    // 3 turns counted 11 700: 3 900 a turn, where the index pulses were
    // 4 000 counts apart every time
    let miscounted = EncoderFigures { moved: 11_700, ..f.clone() };
    assert_eq!(propose_cpr(&miscounted, Some(3)), Ok(4_000));
    // a lone index pulse (no gap measured) leaves the count over the turns
    let one_index = EncoderFigures { moved: 7_202, indexes: 1, gap: None, cpr: None, ..f };
    assert_eq!(propose_cpr(&one_index, Some(3)), Ok(2_400));
}

#[test]
fn a_cpr_the_console_would_refuse_is_not_proposed() {
    let f = parse_encoder(REPLY).unwrap();
    for bad in [0, 2, 1_000_001, u32::MAX] {
        let e = propose_cpr(&EncoderFigures { cpr: Some(bad), ..f.clone() }, None).unwrap_err();
        assert!(e.contains(&format!("cpr={bad}")) && e.contains("4..=1000000 counts per lathe rev"), "{bad}: {e}");
    }
    // 1 000 turns' worth of counts in one turn, past the console's range
    let e = propose_cpr(&EncoderFigures { moved: 4_000_004, cpr: None, gap: None, ..f }, Some(1)).unwrap_err();
    assert!(e.contains("4..=1000000"), "{e}");
}

#[test]
fn a_disagreement_between_the_index_and_the_turns_is_said() {
    let f = parse_encoder(REPLY).unwrap();
    let miscounted = EncoderFigures { moved: 11_700, ..f.clone() };
    let said = crate::cli::device::checks::explain(&miscounted, &propose_cpr(&miscounted, Some(3)), Some(3));
    assert!(said.contains("disagree: 3 turn(s) counted 3900 a turn, the index pulses 4000"), "{said}");
    assert!(said.ends_with("proposed: set cpr 4000   (polyturn device set cpr 4000)"), "{said}");
    // agreeing, or no turns given: nothing to say
    assert_eq!(disagreement(&f, Some(3)), None);
    assert_eq!(disagreement(&miscounted, None), None);
}
