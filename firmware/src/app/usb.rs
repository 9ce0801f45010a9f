//! The USB CDC-ACM console: lines in, the sync core's console protocol,
//! replies out. `watch` streams status lines until the next input.

use super::{settings, tick};
use core::fmt::Write;
use embassy_futures::join::join;
use embassy_futures::select::{select, Either};
use embassy_stm32::peripherals as P;
use embassy_stm32::usb::Driver;
use embassy_stm32::{bind_interrupts, usb, Peri};
use embassy_time::Timer;
use embassy_usb::class::cdc_acm::{CdcAcmClass, State};
use embassy_usb::driver::EndpointError;
use embassy_usb::Builder;
use polyturn_firmware::line::{only_line_ends, route, Line, LineBuffer, Route, PACKET_MAX, TOO_LONG};
use polyturn_sync::cam_upload::{CamHeader, CamUpload, Progress, TableRefusal};
use polyturn_sync::console::{self, tag, Action, Reply};
use polyturn_sync::controller::check_table;
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
    flash: settings::Sectors,
    cam: Option<settings::StoredCam>,
) {
    static UPLOAD: StaticCell<CamUpload> = StaticCell::new();
    let mut store = Store { flash, cam, upload: UPLOAD.init(CamUpload::default()) };
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
    let mut class = CdcAcmClass::new(&mut builder, STATE.init(State::new()), PACKET_MAX as u16);
    let mut dev = builder.build();
    join(dev.run(), async {
        loop {
            class.wait_connection().await;
            let _ = session(&mut class, &mut store).await;
        }
    })
    .await;
}

/// The flash, the cam table fitted from it, and the upload staging buffer:
/// owned by the console task, the only writer.
struct Store {
    flash: settings::Sectors,
    cam: Option<settings::StoredCam>,
    upload: &'static mut CamUpload,
}

async fn session(class: &mut Class, store: &mut Store) -> Result<(), EndpointError> {
    let mut lines = LineBuffer::default();
    let mut packet = [0u8; PACKET_MAX];
    let mut n = class.read_packet(&mut packet).await?;
    loop {
        let mut watching = false;
        for (i, &byte) in packet[..n].iter().enumerate() {
            let (tag, reply, action) = match lines.push(byte) {
                None => continue,
                Some(Line::TooLong) => (Tag::new(), too_long(), Action::None),
                Some(Line::Text(text)) => answer(text, store),
            };
            lines.clear();
            let reply = match action {
                Action::Save => saved(store),
                _ => reply,
            };
            send(class, &tag, &reply).await?;
            if action == Action::Dfu {
                super::dfu::restart().await;
            }
            // `watch` streams until the next input; bytes already received
            // after it are that input (the watch ends before it starts).
            watching = action == Action::Watch && only_line_ends(&packet[i + 1..n]);
        }
        // The packet that ends a watch is the next command: handled, not
        // dropped (dropped, its reply would never come).
        n = if watching { watch(class, &mut packet).await? } else { class.read_packet(&mut packet).await? };
    }
}

/// A reply tag's digits (`console::tag`), copied out of the line buffer.
type Tag = heapless::Vec<u8, { tag::TAG_DIGITS }>;

/// One line's reply (and what to do besides), with its tag.
fn answer(line: &[u8], store: &mut Store) -> (Tag, Reply, Action) {
    let (tag, body) = match route(line) {
        Ok((t, to)) => (Tag::from_slice(t.unwrap_or_default()).unwrap_or_default(), to),
        Err(e) => {
            let mut r = Reply::new();
            let _ = write!(r, "error: {e}");
            return (Tag::new(), r, Action::None);
        }
    };
    let body = match body {
        Route::Cam(args) => return (tag, cam_line(args, store), Action::None),
        Route::Console(body) => body,
    };
    // Parse, derive new settings and render outside the lock the tick
    // shares; inside it only a copy of the settings and `apply_prepared`
    // (short, copies out).
    let cmd = console::parse(body);
    let pre = tick::with_core(|c| (*c.config(), c.config_generation()))
        .and_then(|(cfg, generation)| console::prepare(&cmd, cfg, generation, tick::TIMING));
    let outcome = tick::with_core(|c| console::apply_prepared(cmd, pre.as_ref(), c));
    tick::apply_driver_settings();
    let (reply, action) = match outcome {
        Some(outcome) => console::render(&outcome),
        None => (not_ready(), Action::None),
    };
    (tag, reply, action)
}

fn not_ready() -> Reply {
    text_reply("error: the controller is not running yet")
}

fn too_long() -> Reply {
    text_reply(TOO_LONG)
}

/// Writes the settings. Not under the tick's lock: the erase stalls the
/// CPU (flash busy) for up to 2 s anyway, which is why `save` is refused
/// unless idle with the lathe at rest.
fn saved(store: &mut Store) -> Reply {
    let cfg = tick::with_core(|c| *c.config());
    // what runs is saved: a stored table the X axis no longer runs (`set
    // cpr` took it off, or it did not fit at power-up) is forgotten, never
    // fitted again at the next power-up under other settings
    let cam = store.cam.filter(|_| tick::with_core(|c| c.x_axis().is_some()) == Some(true));
    let mut r = Reply::new();
    let _ = match cfg.map(|c| persist(&mut store.flash, &mut store.cam, &c, cam)) {
        Some(Ok((stall, Fit::Fitted | Fit::NoCam))) => write!(r, "ok saved{}", stall.describe()),
        // saved, but the stored cam no longer fits these settings: say so
        Some(Ok((stall, Fit::Refused(e)))) => write!(r, "ok saved{}; the cam table is off: {e}", stall.describe()),
        Some(Err(())) => write!(r, "error: flash write failed: settings not saved"),
        None => write!(r, "error: the controller is not running yet"),
    };
    r
}

/// What became of the cam after a save.
enum Fit {
    NoCam,
    Fitted,
    Refused(&'static str),
}

/// Saves settings and cam, then re-fits the cam from the new slot (the
/// old slot will be erased by the next save). The erase stalls the CPU:
/// the core is told before and asked after what the lathe did meanwhile
/// (`Controller::begin_stall`). `Err` if the flash failed.
fn persist(
    flash: &mut settings::Sectors,
    fitted: &mut Option<settings::StoredCam>,
    cfg: &polyturn_sync::Config,
    cam: Option<(CamHeader, &[i32])>,
) -> Result<(polyturn_sync::Stall, Fit), ()> {
    tick::begin_stall();
    let saved = settings::save(flash, cfg, cam);
    let stall = tick::with_core(|c| c.end_stall()).unwrap_or_default();
    // the erase lost ticks: the edge times' clock is measured again
    tick::restart_edges();
    let stored = saved?;
    *fitted = stored;
    let Some((h, t)) = stored else { return Ok((stall, Fit::NoCam)) };
    // Never leave the X axis on the old slot's table: the next save erases
    // it. If the table no longer fits (another cpr), the X axis comes off.
    match tick::fit_cam(&h, t) {
        Some(Ok(())) => Ok((stall, Fit::Fitted)),
        other => {
            let _ = tick::with_core(|c| c.set_x_axis(None));
            *fitted = None;
            Ok((
                stall,
                Fit::Refused(match other {
                    Some(Err(e)) => e,
                    _ => "the controller is not running",
                }),
            ))
        }
    }
}

fn text_reply(s: &str) -> Reply {
    let mut r = Reply::new();
    let _ = r.push_str(s);
    r
}

/// `cam off`, or one line of an upload (`args`: what follows `cam`); a
/// complete, checked table is saved to flash with the settings (idle,
/// lathe at rest) and fitted from there.
fn cam_line(args: &[u8], store: &mut Store) -> Reply {
    let args = core::str::from_utf8(args).unwrap_or("?");
    if args.trim() == "off" {
        return match tick::with_core(|c| c.set_x_axis(None)) {
            Some(Ok(())) => {
                store.cam = None;
                text_reply("ok cam off (save to forget it)")
            }
            _ => text_reply("error: stop first: the cam changes only while idle"),
        };
    }
    let mut r = Reply::new();
    let was_uploading = store.upload.in_progress();
    let _ = match store.upload.line(args) {
        Err(e) if was_uploading => write!(r, "error: {e}; the upload is abandoned (start again with cam begin)"),
        Err(e) => write!(r, "error: {e}"),
        Ok(Progress::Begun) => write!(r, "ok cam begin"),
        Ok(Progress::Received(n)) => write!(r, "ok cam {n}"),
        // asked only once a table is complete (not under the lock per chunk)
        Ok(Progress::Complete(h)) => match tick::with_core(console::cam_wait) {
            Some(Some(why)) => write!(r, "error: {why} ({} points kept, send cam end again)", h.points),
            _ => save_table(&h, store, &mut r),
        },
    };
    r
}

/// A complete table, idle with the lathe at rest: every check the fit
/// applies, before anything is saved or replaced (the header under the
/// lock, the points outside it), then saved and fitted.
fn save_table(h: &CamHeader, store: &mut Store, r: &mut Reply) -> core::fmt::Result {
    let (cfg, header) = match tick::with_core(|c| (*c.config(), c.check_cam(h))) {
        Some((cfg, header)) => (Some(cfg), header),
        None => (None, Err("the controller is not running yet")),
    };
    let checked = header.map_err(TableRefusal::from).and_then(|()| {
        store.upload.table().map_or(Err(TableRefusal::Text("cam table incomplete")), |(h, p)| check_table(&h, p))
    });
    match (cfg, checked) {
        (_, Err(e)) => write!(r, "error: {e}"),
        (None, _) => write!(r, "error: the controller is not running yet"),
        (Some(cfg), Ok(())) => match persist(&mut store.flash, &mut store.cam, &cfg, store.upload.table()) {
            Ok((stall, Fit::Fitted)) => write!(r, "ok cam {} points saved and fitted{}", h.points, stall.describe()),
            Ok((_, Fit::Refused(e))) => write!(r, "error: cam saved but not fitted, X axis off: {e}"),
            Ok((_, Fit::NoCam)) => write!(r, "error: cam not saved (the flash kept none)"),
            Err(()) => write!(r, "error: flash write failed: cam not saved"),
        },
    }
}

/// Sends `#tag reply` (or `reply` untagged) and CRLF.
async fn send(class: &mut Class, tag: &[u8], reply: &Reply) -> Result<(), EndpointError> {
    let mut line: heapless::Vec<u8, { console::REPLY_LEN + tag::TAG_DIGITS + 4 }> = heapless::Vec::new();
    if !tag.is_empty() {
        let _ = line.push(b'#');
        let _ = line.extend_from_slice(tag);
        let _ = line.push(b' ');
    }
    let _ = line.extend_from_slice(reply.as_bytes());
    let _ = line.extend_from_slice(b"\r\n");
    for chunk in line.chunks(62) {
        class.write_packet(chunk).await?;
    }
    Ok(())
}

/// Streams status five times a second until any input arrives; returns
/// that input's length (in `buf`) for the session to handle.
async fn watch(class: &mut Class, buf: &mut [u8; PACKET_MAX]) -> Result<usize, EndpointError> {
    loop {
        match select(Timer::after_millis(200), class.read_packet(buf)).await {
            Either::First(()) => {
                if let Some(snap) = tick::with_core(|c| console::Snapshot::of(c)) {
                    let mut line = Reply::new();
                    snap.write(&mut line);
                    send(class, &[], &line).await?;
                }
            }
            Either::Second(Ok(n)) if only_line_ends(&buf[..n]) => {}
            Either::Second(r) => return r,
        }
    }
}
