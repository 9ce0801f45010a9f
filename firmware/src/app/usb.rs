//! The USB CDC-ACM console: lines in, the sync core's console protocol,
//! replies out. `watch` streams status lines until the next input.

use super::{settings, tick};
use embassy_futures::join::join;
use embassy_futures::select::{select, Either};
use embassy_stm32::peripherals as P;
use embassy_stm32::usb::Driver;
use embassy_stm32::{bind_interrupts, usb, Peri};
use embassy_time::Timer;
use embassy_usb::class::cdc_acm::{CdcAcmClass, State};
use embassy_usb::driver::EndpointError;
use embassy_usb::Builder;
use polyturn_firmware::line::{Line, LineBuffer};
use polyturn_sync::console::{self, Action, Reply};
use static_cell::StaticCell;

bind_interrupts!(struct Irqs {
    OTG_FS => usb::InterruptHandler<P::USB_OTG_FS>;
});

type Class = CdcAcmClass<'static, Driver<'static, P::USB_OTG_FS>>;

#[embassy_executor::task]
pub async fn console(
    otg: Peri<'static, P::USB_OTG_FS>,
    dp: Peri<'static, P::PA12>,
    dm: Peri<'static, P::PA11>,
    mut flash: settings::Sectors,
) {
    static EP_OUT: StaticCell<[u8; 256]> = StaticCell::new();
    static CONFIG_DESC: StaticCell<[u8; 256]> = StaticCell::new();
    static BOS_DESC: StaticCell<[u8; 256]> = StaticCell::new();
    static CONTROL: StaticCell<[u8; 64]> = StaticCell::new();
    static STATE: StaticCell<State> = StaticCell::new();
    let mut otg_cfg = usb::Config::default();
    otg_cfg.vbus_detection = false; // the Black Pill does not wire VBUS sensing
    let driver = Driver::new_fs(otg, Irqs, dp, dm, EP_OUT.init([0; 256]), otg_cfg);
    let mut cfg = embassy_usb::Config::new(0x16c0, 0x27dd);
    cfg.manufacturer = Some("polyturn");
    cfg.product = Some("polyturn console");
    cfg.serial_number = Some(env!("CARGO_PKG_VERSION"));
    let mut builder =
        Builder::new(driver, cfg, CONFIG_DESC.init([0; 256]), BOS_DESC.init([0; 256]), &mut [], CONTROL.init([0; 64]));
    let mut class = CdcAcmClass::new(&mut builder, STATE.init(State::new()), 64);
    let mut dev = builder.build();
    join(dev.run(), async {
        loop {
            class.wait_connection().await;
            let _ = session(&mut class, &mut flash).await;
        }
    })
    .await;
}

async fn session(class: &mut Class, flash: &mut settings::Sectors) -> Result<(), EndpointError> {
    let mut lines = LineBuffer::default();
    let mut packet = [0u8; 64];
    loop {
        let n = class.read_packet(&mut packet).await?;
        for &b in &packet[..n] {
            let (reply, action) = match lines.push(b) {
                None => continue,
                Some(Line::TooLong) => (too_long(), Action::None),
                Some(Line::Text(text)) => {
                    // Parse and render outside the lock the tick shares;
                    // only `apply` (short, copies out) runs inside it.
                    let cmd = console::parse(text);
                    let outcome = tick::with_core(|c| console::apply(cmd, c));
                    tick::apply_driver_settings();
                    match outcome {
                        Some(outcome) => console::render(&outcome),
                        None => (not_ready(), Action::None),
                    }
                }
            };
            lines.clear();
            let reply = match action {
                Action::Save => saved(flash),
                _ => reply,
            };
            send(class, &reply).await?;
            if action == Action::Watch {
                watch(class).await?;
            }
        }
    }
}

fn not_ready() -> Reply {
    let mut r = Reply::new();
    let _ = r.push_str("error: the controller is not running yet");
    r
}

fn too_long() -> Reply {
    let mut r = Reply::new();
    let _ = r.push_str("error: line too long (96 characters at most)");
    r
}

/// Writes the settings. Not under the tick's lock: the erase stalls the
/// CPU (flash busy) for up to 2 s anyway, which is why `save` is refused
/// unless idle with the lathe at rest.
fn saved(flash: &mut settings::Sectors) -> Reply {
    let cfg = tick::with_core(|c| *c.config());
    let mut r = Reply::new();
    let ok = cfg.is_some_and(|c| settings::save(flash, &c));
    let _ = r.push_str(if ok { "ok saved" } else { "error: flash write failed: settings not saved" });
    r
}

async fn send(class: &mut Class, reply: &Reply) -> Result<(), EndpointError> {
    for chunk in reply.as_bytes().chunks(62) {
        class.write_packet(chunk).await?;
    }
    class.write_packet(b"\r\n").await
}

/// Streams status five times a second until any input arrives.
async fn watch(class: &mut Class) -> Result<(), EndpointError> {
    let mut buf = [0u8; 64];
    loop {
        match select(Timer::after_millis(200), class.read_packet(&mut buf)).await {
            Either::First(()) => {
                if let Some(snap) = tick::with_core(|c| console::Snapshot::of(c)) {
                    let mut line = Reply::new();
                    snap.write(&mut line);
                    send(class, &line).await?;
                }
            }
            Either::Second(r) => {
                r?;
                return Ok(());
            }
        }
    }
}
