//! The host's schedule (USB 2.0 §7.1.7, §8.4.3): it polls the cable for the
//! device's pull-up, waits TATTDB = 100 ms, resets the bus for TDRST = 10 ms, lets
//! it recover (TRSTRCY = 10 ms), then runs full-speed frames: a SOF every 1 ms
//! (`Otg::sof`; EOPF at DCFG.PFIVL of the frame) and transactions in ten 100 µs
//! slots a frame, up to three each while they progress. A NAK is retried at the
//! next slot. Enumeration is `enumerate`'s; once configured, bytes queued with
//! [`Host::send`] go out on the bulk OUT endpoint and the bulk IN endpoint is polled
//! every slot into [`Host::received`]. Buffers are bounded; a device that never
//! answers, stalls or misdescribes itself ends in [`Host::error`].

use super::control::{Control, Stage, Step};
use super::descriptors::Device;
use polyturn_stm32_model::chip::otg::{Handshake, InReply, Otg};
use std::collections::VecDeque;

mod enumerate;
pub use enumerate::Req;

const SLOTS: u64 = 10;
const DEBOUNCE_MS: u64 = 100;
const RESET_MS: u64 = 10;
const RECOVERY_MS: u64 = 10;
/// §9.2.6.4: a standard request's data stage within 500 ms; the whole transfer
/// is given that here
const CONTROL_MS: u64 = 500;
const BUF_MAX: usize = 16 * 1024;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Detached,
    Debounce(u64),
    Reset(u64),
    Recovery(u64),
    Enumerate,
    Configured,
    Failed,
}

pub struct Host {
    phase: Phase,
    /// the cycle of the next slot, the slot in the frame, the frame number
    next: u64,
    slot: u64,
    frame: u16,
    sof: bool,
    /// cycles per ms at the last step; the time of the slot being run
    ms: u64,
    t: u64,
    req: Option<Req>,
    ctl: Option<Control>,
    pause_until: u64,
    addr: u8,
    pub dev: Device,
    lang: u16,
    pub strings: Vec<String>,
    pub attached_at: Option<u64>,
    pub configured_at: Option<u64>,
    error: Option<String>,
    tx: VecDeque<u8>,
    rx: Vec<u8>,
}

impl Default for Host {
    fn default() -> Host {
        Host {
            phase: Phase::Detached,
            next: 0,
            slot: 0,
            frame: 0,
            sof: false,
            ms: 96_000,
            t: 0,
            req: None,
            ctl: None,
            pause_until: 0,
            addr: 0,
            dev: Device { mps0: 8, ..Device::default() },
            lang: 0,
            strings: Vec::new(),
            attached_at: None,
            configured_at: None,
            error: None,
            tx: VecDeque::new(),
            rx: Vec::new(),
        }
    }
}

impl Host {
    /// Runs every slot due by CPU cycle `now` (SYSCLK `sysclk` Hz).
    pub fn step(&mut self, now: u64, sysclk: u64, otg: &mut Otg) {
        self.ms = (sysclk / 1000).max(SLOTS);
        if self.next == 0 {
            self.next = now.max(1);
        }
        while self.next <= now {
            self.t = self.next;
            self.run_slot(otg);
            self.next += self.ms / SLOTS;
        }
    }

    /// The cycle of the next slot (always after the last step's `now`).
    pub fn next_event(&self) -> u64 {
        self.next
    }

    pub fn configured(&self) -> bool {
        self.phase == Phase::Configured
    }

    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Queues bytes for the bulk OUT endpoint; false (nothing queued) if over the
    /// bound.
    pub fn send(&mut self, bytes: &[u8]) -> bool {
        let ok = self.tx.len() + bytes.len() <= BUF_MAX;
        if ok {
            self.tx.extend(bytes);
        }
        ok
    }

    /// Bytes received on the bulk IN endpoint so far, taken.
    pub fn received(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.rx)
    }

    /// The last ms of the bus's frames: SOF at slot 0, EOPF at PFIVL.
    fn frame_marks(&mut self, otg: &mut Otg) {
        if !self.sof {
            return;
        }
        if self.slot == 0 {
            self.frame = (self.frame + 1) & 0x7FF;
            otg.sof(self.frame);
        }
        if self.slot == (otg.periodic_frame_percent() as u64 * SLOTS / 100).min(SLOTS - 1) {
            otg.end_of_periodic_frame();
        }
    }

    fn run_slot(&mut self, otg: &mut Otg) {
        self.frame_marks(otg);
        self.slot = (self.slot + 1) % SLOTS;
        let (t, ms) = (self.t, self.ms);
        self.phase = match self.phase {
            Phase::Detached if otg.pulled_up() => {
                self.attached_at.get_or_insert(t);
                Phase::Debounce(t + DEBOUNCE_MS * ms)
            }
            Phase::Debounce(_) if !otg.pulled_up() => Phase::Detached,
            Phase::Debounce(end) if t >= end => {
                otg.bus_reset();
                self.sof = false;
                Phase::Reset(t + RESET_MS * ms)
            }
            Phase::Reset(end) if t >= end => {
                otg.reset_done();
                self.sof = true;
                Phase::Recovery(t + RECOVERY_MS * ms)
            }
            Phase::Recovery(end) if t >= end => {
                self.req = Some(Req::Device8);
                Phase::Enumerate
            }
            Phase::Enumerate | Phase::Configured if !otg.pulled_up() => self.fail("the device disconnected".into()),
            Phase::Enumerate => self.control(otg),
            Phase::Configured => self.bulk(otg),
            p => p,
        };
    }

    fn fail(&mut self, e: String) -> Phase {
        self.error.get_or_insert(e);
        Phase::Failed
    }

    /// Up to three transactions of the control transfer under way (or the start of
    /// the next request).
    fn control(&mut self, otg: &mut Otg) -> Phase {
        if self.t < self.pause_until {
            return self.phase;
        }
        let Some(mut ctl) = self.ctl.take() else {
            return match self.req {
                Some(r) => {
                    self.ctl = Some(self.start(r));
                    self.phase
                }
                None => Phase::Configured,
            };
        };
        for _ in 0..3 {
            match ctl.transact(otg, self.addr, self.dev.mps0) {
                Step::Progress if ctl.stage == Stage::Done => return self.finished(ctl),
                Step::Progress => {}
                Step::Wait if self.t - ctl.started > CONTROL_MS * self.ms => {
                    let stage = ctl.stage;
                    return self.fail(format!("{}: not done within {CONTROL_MS} ms (NAKed in {stage:?})", ctl.name));
                }
                Step::Wait => break,
                Step::Failed(e) => return self.fail(e),
            }
        }
        self.ctl = Some(ctl);
        self.phase
    }

    /// One bulk OUT packet if bytes wait, and an IN poll.
    fn bulk(&mut self, otg: &mut Otg) -> Phase {
        let (addr, d) = (self.addr, self.dev.clone());
        if !self.tx.is_empty() {
            let chunk: Vec<u8> = self.tx.iter().take(d.bulk_mps).copied().collect();
            match otg.out(addr, d.bulk_out as usize, &chunk) {
                Handshake::Ack => drop(self.tx.drain(..chunk.len())),
                Handshake::Nak => {}
                h => return self.fail(format!("bulk OUT endpoint {}: {h:?}", d.bulk_out)),
            }
        }
        match otg.in_token(addr, d.bulk_in as usize) {
            InReply::Data(p) if self.rx.len() + p.len() <= BUF_MAX => self.rx.extend(p),
            InReply::Data(_) => return self.fail("more than 16 KiB received and not read".into()),
            InReply::Nak => {}
            r => return self.fail(format!("bulk IN endpoint {}: {r:?}", d.bulk_in)),
        }
        Phase::Configured
    }
}

#[cfg(test)]
mod tests {
    use super::Host;
    use polyturn_stm32_model::chip::otg::{reg, Otg};

    const MS: u64 = 96_000;

    /// The core pulled up with no firmware behind it: SETUPs are taken, nothing
    /// ever answers the data stage.
    fn silent() -> Otg {
        let mut otg = Otg::default();
        otg.write(reg::GCCFG, 1 << 16 | 1 << 21, u32::MAX);
        otg.write(reg::GRXFSIZ, 46, u32::MAX);
        otg
    }

    fn run(h: &mut Host, otg: &mut Otg, from_ms: u64, to_ms: u64) {
        for t in from_ms..=to_ms {
            h.step(t * MS, 96_000_000, otg);
        }
    }

    #[test]
    fn a_device_that_never_answers_is_named_after_500_ms() {
        let (mut h, mut otg) = (Host::default(), silent());
        run(&mut h, &mut otg, 1, 600);
        assert_eq!(h.error(), None, "reset at 101 ms, first request at 121 ms");
        assert_ne!(otg.read(reg::DSTS) >> 8 & 0x3FFF, 0, "SOFs since the reset");
        run(&mut h, &mut otg, 601, 700);
        assert_eq!(h.error(), Some("GET_DESCRIPTOR device (8 bytes): not done within 500 ms (NAKed in DataIn)"));
        assert_eq!(h.attached_at, Some(MS));
        assert!(!h.configured());
    }

    #[test]
    fn a_disconnect_during_enumeration_is_an_error() {
        let (mut h, mut otg) = (Host::default(), silent());
        run(&mut h, &mut otg, 1, 150);
        otg.write(reg::DCTL, 1 << 1, u32::MAX);
        run(&mut h, &mut otg, 151, 152);
        assert_eq!(h.error(), Some("the device disconnected"));
    }

    #[test]
    fn the_send_buffer_is_bounded() {
        let mut h = Host::default();
        assert!(h.send(&[0; 16 * 1024]));
        assert!(!h.send(&[0]));
    }
}
