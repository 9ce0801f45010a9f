//! One control transfer as a host runs it (USB 2.0 §8.5.3): SETUP, then IN or OUT
//! data packets, then the status stage in the other direction (a zero-length
//! packet). NAKed transactions are retried at the host's next slot; a STALL, a
//! missing answer or a malformed stage ends the transfer with the request's name.

use polyturn_stm32_model::chip::otg::{Handshake, InReply, Otg};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Setup,
    DataIn,
    DataOut(usize),
    StatusIn,
    StatusOut,
    Done,
}

pub struct Control {
    pub name: String,
    setup: [u8; 8],
    out: Vec<u8>,
    pub got: Vec<u8>,
    pub stage: Stage,
    pub started: u64,
}

/// How one transaction went.
pub enum Step {
    /// the stage moved on (or the transfer ended: `stage == Done`)
    Progress,
    /// NAKed: try again later
    Wait,
    Failed(String),
}

impl Control {
    pub fn new(name: &str, setup: [u8; 8], out: Vec<u8>, now: u64) -> Control {
        Control { name: name.into(), setup, out, got: Vec::new(), stage: Stage::Setup, started: now }
    }

    fn length(&self) -> usize {
        u16::from_le_bytes([self.setup[6], self.setup[7]]) as usize
    }

    fn after_setup(&self) -> Stage {
        match (self.length(), self.setup[0] & 0x80 != 0) {
            (0, _) => Stage::StatusIn,
            (_, true) => Stage::DataIn,
            _ => Stage::DataOut(0),
        }
    }

    fn fail(&self, what: &str) -> Step {
        Step::Failed(format!("{}: {what} in the {:?} stage", self.name, self.stage))
    }

    /// One transaction of the current stage to `addr` with EP0 packets of `mps0`.
    pub fn transact(&mut self, otg: &mut Otg, addr: u8, mps0: usize) -> Step {
        match self.stage {
            Stage::Setup => match otg.setup(addr, self.setup) {
                Handshake::Ack => self.to(self.after_setup()),
                Handshake::Timeout => self.fail("no answer to SETUP"),
                h => self.fail(&format!("SETUP answered {h:?} (must be ACKed)")),
            },
            Stage::DataIn => match otg.in_token(addr, 0) {
                InReply::Data(p) => {
                    let short = p.len() < mps0;
                    if p.len() > mps0 || self.got.len() + p.len() > self.length() {
                        return self.fail(&format!(
                            "a {}-byte packet (max {mps0}, wLength {})",
                            p.len(),
                            self.length()
                        ));
                    }
                    self.got.extend(p);
                    let done = short || self.got.len() == self.length();
                    if done {
                        self.to(Stage::StatusOut)
                    } else {
                        Step::Progress
                    }
                }
                r => self.handshake(r),
            },
            Stage::DataOut(at) => {
                let end = (at + mps0).min(self.out.len());
                match otg.out(addr, 0, &self.out[at..end]) {
                    Handshake::Ack if end == self.out.len() => self.to(Stage::StatusIn),
                    Handshake::Ack => self.to(Stage::DataOut(end)),
                    h => self.handshake_out(h),
                }
            }
            Stage::StatusOut => match otg.out(addr, 0, &[]) {
                Handshake::Ack => self.to(Stage::Done),
                h => self.handshake_out(h),
            },
            Stage::StatusIn => match otg.in_token(addr, 0) {
                InReply::Data(p) if p.is_empty() => self.to(Stage::Done),
                InReply::Data(p) => self.fail(&format!("{} bytes in the status stage (must be none)", p.len())),
                r => self.handshake(r),
            },
            Stage::Done => Step::Progress,
        }
    }

    fn to(&mut self, s: Stage) -> Step {
        self.stage = s;
        Step::Progress
    }

    fn handshake(&self, r: InReply) -> Step {
        match r {
            InReply::Nak => Step::Wait,
            InReply::Stall => self.fail("STALL"),
            _ => self.fail("no answer to IN"),
        }
    }

    fn handshake_out(&self, h: Handshake) -> Step {
        match h {
            Handshake::Nak => Step::Wait,
            Handshake::Stall => self.fail("STALL"),
            _ => self.fail("no answer to OUT"),
        }
    }
}

/// A standard or class SETUP packet (§9.3).
pub fn setup(request_type: u8, request: u8, value: u16, index: u16, length: u16) -> [u8; 8] {
    let (v, i, l) = (value.to_le_bytes(), index.to_le_bytes(), length.to_le_bytes());
    [request_type, request, v[0], v[1], i[0], i[1], l[0], l[1]]
}

#[cfg(test)]
mod tests {
    use super::{setup, Control, Stage, Step};
    use polyturn_stm32_model::chip::otg::{reg, Otg};

    #[test]
    fn a_stalled_standard_request_is_named_with_its_stage() {
        let mut otg = Otg::default();
        otg.write(reg::GCCFG, 1 << 16 | 1 << 21, u32::MAX);
        otg.write(reg::GRXFSIZ, 46, u32::MAX);
        otg.bus_reset();
        otg.reset_done();
        let mut c = Control::new("GET_DESCRIPTOR device", setup(0x80, 6, 0x0100, 0, 18), vec![], 0);
        assert!(matches!(c.transact(&mut otg, 0, 64), Step::Progress));
        assert_eq!(c.stage, Stage::DataIn);
        assert!(matches!(c.transact(&mut otg, 0, 64), Step::Wait), "NAK: the firmware has not answered");
        otg.write(reg::DIEPCTL, 1 << 21, u32::MAX); // the firmware rejects it
        let Step::Failed(e) = c.transact(&mut otg, 0, 64) else { panic!("expected a failure") };
        assert_eq!(e, "GET_DESCRIPTOR device: STALL in the DataIn stage");
        assert!(matches!(c.transact(&mut otg, 9, 64), Step::Failed(e) if e.contains("no answer to IN")));
    }
}
