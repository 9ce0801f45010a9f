//! Any bytes, line by line, into the console: always one `ok`/`error:`
//! line back, never a panic, and an error never changes a setting.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polyturn_sync::{console, Config, Controller, Timing};

fuzz_target!(|data: &[u8]| {
    let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
    for line in data.split(|&b| b == b'\n') {
        let before = *ctl.config();
        let (reply, _) = console::handle(line, &mut ctl);
        assert!(reply.starts_with("ok") || reply.starts_with("error: "));
        if reply.starts_with("error") {
            assert_eq!(*ctl.config(), before);
        }
        assert_eq!(ctl.config().validate(), Ok(()));
    }
});
