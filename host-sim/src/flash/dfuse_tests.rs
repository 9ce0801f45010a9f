//! The flash procedure against the fake ROM bootloader: what lands in
//! flash, what is never touched, and what a fault becomes.

use super::dfuse::io as dfuse_io;
use super::dfuse::{flash, FlashError, Left, Limits, Report};
use super::image::{from_bytes, Format};
use super::Image;
use super::{sector_start, APP_END, FLASH_BASE};
use polyturn_bench::flash::fake::{Event, FakeRom, Faults, INTERFACE};
use polyturn_bench::flash::testkit::good;
use std::time::{Duration, Instant};

const SETTINGS: u32 = APP_END;
const SETTINGS_BYTES: usize = 256 * 1024;

/// A release image of `len` bytes with its seal (`len` a multiple of 4).
fn image(len: usize) -> Image {
    from_bytes(&good(len - 12), Format::Bin, false).unwrap()
}

fn quick() -> Limits {
    Limits { step: Duration::from_millis(300), poll_max: Duration::from_millis(2) }
}

/// A board as found: an old firmware in sectors 0-5, settings in 6-7.
fn board(faults: Faults) -> (FakeRom, Vec<u8>) {
    let rom = FakeRom::new(faults);
    rom.preload(FLASH_BASE, &vec![0x5A; (APP_END - FLASH_BASE) as usize]);
    let settings: Vec<u8> = (0..SETTINGS_BYTES).map(|i| (i % 251) as u8).collect();
    rom.preload(SETTINGS, &settings);
    (rom, settings)
}

fn run(rom: &FakeRom, image: &Image) -> Result<Report, FlashError> {
    flash(rom, image, &quick(), &mut |_| {})
}

#[test]
fn the_image_lands_byte_exact_and_the_settings_survive() {
    for len in [3000, 100 * 1024, 256 * 1024] {
        let (rom, settings) = board(Faults::default());
        let img = image(len);
        let report = run(&rom, &img).unwrap();
        assert_eq!(
            report,
            Report { written_bytes: len, sectors_erased: super::last_sector(len as u32) + 1, left: Left::Manifest }
        );
        assert_eq!(rom.read(FLASH_BASE, len), img.bytes, "{len}");
        // the rest of the erased sectors is erased, not the old firmware
        let erased_end = sector_start(super::last_sector(len as u32) + 1);
        assert!(rom.read(FLASH_BASE + len as u32, (erased_end - FLASH_BASE) as usize - len).iter().all(|&b| b == 0xFF));
        assert_eq!(rom.read(SETTINGS, SETTINGS_BYTES), settings, "{len}: sectors 6-7 changed");
        let events = rom.events();
        assert!(events.iter().all(|e| match e {
            Event::Erase(a) => *a < APP_END,
            Event::Write { address, len } => address + *len as u32 <= APP_END,
            Event::MassErase => false,
            _ => true,
        }));
    }
}

#[test]
fn leave_is_sent_last_after_the_read_back_and_from_the_vector_table() {
    let (rom, _) = board(Faults::default());
    let mut seen = Vec::new();
    flash(&rom, &image(20_000), &quick(), &mut |p| seen.push(p)).unwrap();
    let events = rom.events();
    let n = events.len();
    assert_eq!(&events[n - 2..], &[Event::SetAddress(FLASH_BASE), Event::Leave]);
    let last_upload = events.iter().rposition(|e| matches!(e, Event::Upload { .. })).unwrap();
    let last_write = events.iter().rposition(|e| matches!(e, Event::Write { .. })).unwrap();
    assert!(last_write < last_upload && last_upload < n - 2);
    let uploaded: usize = events.iter().map(|e| if let Event::Upload { len, .. } = e { *len } else { 0 }).sum();
    assert_eq!(uploaded, 20_480, "every written byte is read back, in whole transfers");
    assert_eq!(seen.last(), Some(&super::dfuse::Progress::Leaving));
    assert_eq!(rom.state(), dfu_core::State::DfuManifest);
}

#[test]
fn verify_catches_a_byte_that_did_not_program() {
    let img = image(40_000);
    let address = FLASH_BASE + 0x1234;
    let bit = img.bytes[0x1234].trailing_zeros().min(7); // a bit that is 1 there
    let (rom, settings) = board(Faults { stuck_low: Some((address, 1 << bit)), ..Faults::default() });
    let e = run(&rom, &img).unwrap_err();
    let read = img.bytes[0x1234] & !(1 << bit);
    assert_eq!(e, FlashError::Verify { address, wrote: img.bytes[0x1234], read });
    assert!(e.to_string().starts_with("verify failed at 0x08001234"), "{e}");
    assert!(!rom.events().contains(&Event::Leave), "a bad image must not be started");
    assert_eq!(rom.read(SETTINGS, SETTINGS_BYTES), settings);
}

#[test]
fn a_usb_error_anywhere_is_one_error_and_no_leave_before_verify() {
    let img = image(6000);
    let total = {
        let (rom, _) = board(Faults::default());
        run(&rom, &img).unwrap();
        rom.transfers()
    };
    for n in 0..total {
        let (rom, settings) = board(Faults { usb_error_at: Some(n), ..Faults::default() });
        match run(&rom, &img) {
            // the ROM may vanish before answering the last GETSTATUS
            Ok(r) => assert_eq!((n, r.left), (total - 1, Left::Vanished)),
            Err(e @ FlashError::Usb { .. }) => {
                let text = e.to_string();
                assert!(
                    text.starts_with("USB transfer failed during the ") && text.ends_with(": pipe error (injected)"),
                    "{n}: {text}"
                );
                assert!(!rom.events().contains(&Event::Leave), "{n}: left DFU after {text}");
            }
            Err(e) => panic!("transfer {n}: {e}"),
        }
        assert_eq!(rom.read(SETTINGS, SETTINGS_BYTES), settings);
    }
}

#[test]
fn a_device_left_in_error_or_mid_transfer_is_brought_back_to_idle() {
    let (rom, _) = board(Faults::default());
    assert!(dfu_core::DfuIo::write_control(&rom, 0x21, 1, 1, &[0; 4]).is_err()); // block 1: stalled
    assert_eq!(rom.state(), dfu_core::State::DfuError);
    run(&rom, &image(5000)).unwrap();
    assert_eq!(rom.events()[0], Event::ClearStatus);
    let e = dfuse_io::command(&FakeRom::new(Faults::default()), 0x21, 0x1000_0000, "the address", &quick());
    assert_eq!(
        e.unwrap_err().to_string(),
        "the bootloader refused the address: errTARGET (an address the bootloader does not allow)"
    );
}

#[test]
fn a_device_that_stays_busy_or_asks_for_long_polls_is_bounded() {
    let t = Instant::now();
    let (rom, _) = board(Faults { stuck_busy: true, ..Faults::default() });
    assert!(matches!(run(&rom, &image(5000)), Err(FlashError::Timeout { .. })));
    let (rom, _) = board(Faults { poll_ms: 0xFF_FFFF, ..Faults::default() });
    run(&rom, &image(5000)).unwrap();
    assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
}

#[test]
fn a_device_whose_erase_would_reach_the_settings_is_refused_before_any_request() {
    for interface in
        ["@Internal Flash  /0x08000000/01*512Kg", "@Internal Flash  /0x08004000/04*016Kg,01*064Kg,03*128Kg"]
    {
        let rom = FakeRom::with_interface(interface, Faults::default());
        assert!(matches!(run(&rom, &image(5000)), Err(FlashError::Refused(_))), "{interface}");
        assert_eq!(rom.transfers(), 0);
    }
    let rom = FakeRom::with_interface(INTERFACE, Faults::default());
    assert!(run(&rom, &image(5000)).is_ok());
}

#[test]
fn the_fake_erases_whole_sectors_and_programs_like_nor_flash() {
    let rom = FakeRom::new(Faults::default());
    let io = |v: u16, d: &[u8]| dfu_core::DfuIo::write_control(&rom, 0x21, 1, v, d).map(drop);
    let status = || dfuse_io::status(&rom, "t").map(|s| s.2);
    rom.preload(sector_start(4), &[0x00; 64]);
    io(0, &[0x41, 0x10, 0x00, 0x01, 0x08]).unwrap(); // erase at 0x08010010: sector 4
    assert_eq!((status(), status()), (Ok(dfu_core::State::DfuDnbusy), Ok(dfu_core::State::DfuDnloadIdle)));
    assert_eq!(rom.read(sector_start(4), 64), vec![0xFF; 64]);
    io(0, &[0x21, 0x00, 0x00, 0x01, 0x08]).unwrap();
    let _ = (status(), status());
    io(2, &[0xF0; 2048]).unwrap();
    let _ = (status(), status());
    io(2, &[0x3C; 2048]).unwrap(); // over programmed bytes: AND
    let _ = (status(), status());
    assert_eq!(rom.read(sector_start(4), 2), vec![0x30, 0x30]);
}
