//! Finding the STM32 ROM bootloader on USB (nusb: pure Rust, no libusb)
//! and opening its internal-flash DFU interface with dfu-nusb.
//!
//! AN2606 (STM32F411xC/E, system memory boot): USB DFU on PA11/PA12 as
//! VID 0x0483, PID 0xDF11, DfuSe 1.1a, one interface whose alternate
//! settings name the memories, the first `@Internal Flash  /0x08000000/
//! 04*016Kg,01*064Kg,03*128Kg` (the DfuSe string as dfu-util's dfuse_mem.c
//! reads it: start address, then count*size, K for KiB, g = readable,
//! erasable and writable).

use super::{FLASH_BASE, SECTOR_KIB};
use dfu_core::DfuProtocol;
use dfu_nusb::DfuNusb;
use nusb::MaybeFuture;
use std::future::Future;
use std::sync::Arc;
use std::task::{Context, Poll, Wake};
use std::time::{Duration, Instant};

pub const VID: u16 = 0x0483;
pub const PID: u16 = 0xDF11;
/// USB class "application specific", subclass DFU (DFU 1.1 §4.2.3).
const DFU_CLASS: (u8, u8) = (0xFE, 0x01);
const FLASH_ALT: &str = "@Internal Flash";
/// A string descriptor or setting the interface is a control transfer or
/// two; dfu-nusb gives each 3 s.
const OPEN_WAIT: Duration = Duration::from_secs(10);
const LOOK_EVERY: Duration = Duration::from_millis(250);

/// Waits up to `wait` for the bootloader, and opens its flash interface;
/// Err is one sentence for the user.
pub fn open(wait: Duration) -> Result<DfuNusb, String> {
    let deadline = Instant::now() + wait;
    let info = loop {
        let mut devices = nusb::list_devices().wait().map_err(|e| format!("cannot list USB devices: {e}"))?;
        if let Some(info) = devices.find(|d| d.vendor_id() == VID && d.product_id() == PID) {
            break info;
        }
        let now = Instant::now();
        if now >= deadline {
            return Err(format!(
                "no STM32 bootloader (USB {VID:04x}:{PID:04x}) found within {} s: hold BOOT0, tap NRST, release BOOT0 (or run `polyturn device dfu`), then try again",
                wait.as_secs_f64()
            ));
        }
        std::thread::sleep(LOOK_EVERY.min(deadline - now));
    };
    #[cfg(windows)]
    windows_driver(info.driver())?;
    let device = info.open().wait().map_err(open_error)?;
    let (interface, alt) = flash_alt(&device)?;
    let claimed = device.claim_interface(interface).wait().map_err(open_error)?;
    match block_on(DfuNusb::open(device, claimed, alt), OPEN_WAIT) {
        Some(Ok(dfu)) => Ok(dfu),
        Some(Err(e)) => Err(format!("cannot open the bootloader's flash interface: {e}")),
        None => Err(format!("the bootloader did not answer within {} s", OPEN_WAIT.as_secs())),
    }
}

fn open_error(e: nusb::Error) -> String {
    match e.kind() {
        nusb::ErrorKind::PermissionDenied => no_permission(),
        nusb::ErrorKind::Busy => {
            "the STM32 bootloader is in use by another program (dfu-util, STM32CubeProgrammer?)".into()
        }
        // Windows: nusb opens only what WinUSB drives
        nusb::ErrorKind::Unsupported if cfg!(windows) => no_winusb(None),
        _ => format!("cannot open the STM32 bootloader: {e}"),
    }
}

fn no_permission() -> String {
    format!(
        "no permission to open the STM32 bootloader (USB {VID:04x}:{PID:04x}): install the udev rule of docs/src/flashing.md (\"Let your PC reach the board\"), the release bundle's 70-polyturn.rules: SUBSYSTEM==\"usb\", ATTRS{{idVendor}}==\"0483\", ATTRS{{idProduct}}==\"df11\", TAG+=\"uaccess\" in /etc/udev/rules.d/70-polyturn.rules, then `sudo udevadm control --reload-rules` and replug"
    )
}

/// On Windows, nusb reaches a device only through WinUSB (nusb's
/// `claim_interface` refuses any other driver), and Windows does not bind
/// WinUSB to the ROM bootloader by itself (ST's own tools bind their
/// STTub30 driver instead): it must be bound once by hand. `driver` is the
/// one Windows bound, if any.
pub fn windows_driver(driver: Option<&str>) -> Result<(), String> {
    match driver {
        Some(d) if d.eq_ignore_ascii_case("winusb") => Ok(()),
        other => Err(no_winusb(other)),
    }
}

fn no_winusb(driver: Option<&str>) -> String {
    let bound = match driver {
        Some(d) => format!("Windows drives it with '{}'", crate::cli::errors::escaped(d)),
        None => "Windows has no usable driver for it".into(),
    };
    format!(
        "the STM32 bootloader (USB {VID:04x}:{PID:04x}) is there, but {bound}, and polyturn flash needs WinUSB: bind it once with Zadig (Options > List All Devices, choose \"STM32 BOOTLOADER\", WinUSB, Install Driver or Replace Driver), as docs/src/flashing.md says (\"Let your PC reach the board\"), then run polyturn flash again"
    )
}

/// The DFU interface and alternate setting named `@Internal Flash`, once
/// its layout is the F411's.
fn flash_alt(device: &nusb::Device) -> Result<(u8, u8), String> {
    let config = device.active_configuration().map_err(|e| format!("cannot read the bootloader's descriptors: {e}"))?;
    let lang = nusb::descriptors::language_id::US_ENGLISH;
    for alt in config.interface_alt_settings().filter(|a| (a.class(), a.subclass()) == DFU_CLASS) {
        let Some(index) = alt.string_index() else { continue };
        let Ok(name) = device.get_string_descriptor(index, lang, Duration::from_secs(3)).wait() else { continue };
        if name.starts_with(FLASH_ALT) {
            check_layout(&name)?;
            return Ok((alt.interface_number(), alt.alternate_setting()));
        }
    }
    Err(format!("the device {VID:04x}:{PID:04x} offers no '{FLASH_ALT}' memory: not an STM32 ROM bootloader"))
}

/// The F411's flash exactly: from FLASH_BASE, sectors of 16, 16, 16, 16,
/// 64, 128, 128, 128 KiB (512 KiB). Another layout is another chip (an
/// F401xC has 256 KiB, an F405 1 MiB), whose sectors 6-7 are elsewhere.
pub fn check_layout(name: &str) -> Result<(), String> {
    let shown: String = crate::cli::errors::escaped(name).chars().take(120).collect();
    let refused = || {
        format!(
            "the bootloader's flash is '{shown}', not the STM32F411CE's 512 KiB from 0x{FLASH_BASE:08x}: another chip?"
        )
    };
    match DfuProtocol::new(name, (0x01, 0x1A)) {
        Ok(DfuProtocol::Dfuse { address, memory_layout }) => {
            let want = SECTOR_KIB.iter().map(|k| k * 1024);
            if address == FLASH_BASE && memory_layout.iter().copied().eq(want) {
                return Ok(());
            }
            Err(refused())
        }
        _ => Err(refused()),
    }
}

/// Runs an async nusb/dfu-nusb call to completion on this thread, or gives
/// up after `within` (the future, and its transfers, dropped).
fn block_on<F: Future>(fut: F, within: Duration) -> Option<F::Output> {
    struct Unpark(std::thread::Thread);
    impl Wake for Unpark {
        fn wake(self: Arc<Self>) {
            self.0.unpark();
        }
    }
    let waker = Arc::new(Unpark(std::thread::current())).into();
    let mut cx = Context::from_waker(&waker);
    let mut fut = std::pin::pin!(fut);
    let deadline = Instant::now() + within;
    loop {
        if let Poll::Ready(out) = fut.as_mut().poll(&mut cx) {
            return Some(out);
        }
        let now = Instant::now();
        if now >= deadline {
            return None;
        }
        std::thread::park_timeout(deadline - now);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_f411_flash_layout_is_taken() {
        assert_eq!(check_layout("@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg"), Ok(()));
        for other in [
            "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,01*128Kg", // F401xC, 256 KiB
            "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,07*128Kg", // F405, 1 MiB
            "@Internal Flash  /0x08000000/128*002Kg",                  // F103, pages
            "@Internal Flash  /0x08004000/04*016Kg,01*064Kg,03*128Kg",
            "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg,01*128Kg",
            "@Internal Flash",
            "@Internal Flash  /0x08000000/x*\n",
        ] {
            let e = check_layout(other).unwrap_err();
            assert!(e.contains("another chip") && !e.contains('\n'), "{other}: {e}");
        }
    }

    #[test]
    fn on_windows_only_winusb_reaches_the_bootloader_and_anything_else_says_how_to_bind_it() {
        assert_eq!(windows_driver(Some("WinUSB")), Ok(()));
        for other in [None, Some("usbccgp"), Some("STTub30"), Some("libusbK")] {
            let e = windows_driver(other).unwrap_err();
            assert!(e.starts_with("the STM32 bootloader (USB 0483:df11) is there, but "), "{e}");
            assert!(e.contains("needs WinUSB: bind it once with Zadig") && e.contains("docs/src/flashing.md"), "{e}");
        }
        assert!(windows_driver(Some("STTub30")).unwrap_err().contains("Windows drives it with 'STTub30'"));
    }

    #[test]
    fn a_future_that_never_ends_is_given_up() {
        let t = Instant::now();
        assert_eq!(block_on(std::future::pending::<()>(), Duration::from_millis(50)), None);
        assert!(t.elapsed() < Duration::from_secs(2));
        assert_eq!(block_on(async { 7 }, Duration::from_millis(50)), Some(7));
    }
}

#[cfg(test)]
mod rule_tests {
    /// The permission error quotes the bootloader's line of the one rules file
    /// the book includes and the release bundle ships.
    #[test]
    fn the_permission_error_quotes_the_shipped_udev_rule() {
        let rules = include_str!("../../../docs/src/70-polyturn.rules");
        let line = rules.lines().find(|l| l.contains("df11")).expect("the bootloader's rule");
        let e = super::no_permission();
        assert!(e.contains(line), "{e}");
    }
}
