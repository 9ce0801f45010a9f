//! The requests of enumeration, in a real host's order (USB 2.0 §9.1.2, §9.4;
//! CDC PSTN §6.3): the device descriptor's first 8 bytes (for bMaxPacketSize0)
//! at address 0, SET_ADDRESS (then TDSETADDR = 2 ms, §9.2.6.3), the whole device
//! descriptor, the configuration's 9 bytes then all wTotalLength, string 0 and
//! the three strings it names, SET_CONFIGURATION, then the CDC-ACM requests a
//! terminal program sends on opening the port: SET_LINE_CODING 115200 8N1 and
//! SET_CONTROL_LINE_STATE with DTR and RTS.

use super::{Host, Phase};
use crate::usb::control::{setup, Control};
use crate::usb::descriptors as d;

/// The address the host gives the device.
pub const ADDRESS: u8 = 5;
/// The strings the firmware names (firmware/src/app/usb.rs).
pub const STRINGS: [(&str, &str); 3] =
    [("iManufacturer", "polyturn"), ("iProduct", "polyturn console"), ("iSerialNumber", env!("CARGO_PKG_VERSION"))];
const LINE_CODING: [u8; 7] = [0x00, 0xC2, 0x01, 0x00, 0, 0, 8];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Req {
    Device8,
    SetAddress,
    Device,
    Config9,
    Config(u16),
    Lang,
    Str(usize),
    SetConfig,
    LineCoding,
    LineState,
}

impl Host {
    pub(super) fn start(&self, r: Req) -> Control {
        let (get, dev) = (0x80, &self.dev);
        let (name, s, out) = match r {
            Req::Device8 => ("GET_DESCRIPTOR device (8 bytes)".into(), setup(get, 6, 0x0100, 0, 8), vec![]),
            Req::SetAddress => (format!("SET_ADDRESS {ADDRESS}"), setup(0, 5, ADDRESS as u16, 0, 0), vec![]),
            Req::Device => ("GET_DESCRIPTOR device".into(), setup(get, 6, 0x0100, 0, 18), vec![]),
            Req::Config9 => ("GET_DESCRIPTOR configuration (9 bytes)".into(), setup(get, 6, 0x0200, 0, 9), vec![]),
            Req::Config(n) => ("GET_DESCRIPTOR configuration".into(), setup(get, 6, 0x0200, 0, n), vec![]),
            Req::Lang => ("GET_DESCRIPTOR string 0".into(), setup(get, 6, 0x0300, 0, 255), vec![]),
            Req::Str(i) => {
                let idx = dev.strings[i.min(2)];
                (format!("GET_DESCRIPTOR string {idx}"), setup(get, 6, 0x0300 | idx as u16, self.lang, 255), vec![])
            }
            Req::SetConfig => {
                let v = dev.config_value as u16;
                (format!("SET_CONFIGURATION {v}"), setup(0, 9, v, 0, 0), vec![])
            }
            Req::LineCoding => {
                ("SET_LINE_CODING".into(), setup(0x21, 0x20, 0, dev.comm as u16, 7), LINE_CODING.to_vec())
            }
            Req::LineState => {
                ("SET_CONTROL_LINE_STATE DTR RTS".into(), setup(0x21, 0x22, 3, dev.comm as u16, 0), vec![])
            }
        };
        Control::new(&name, s, out, self.t)
    }

    /// A request done: its answer checked, and the next request chosen.
    pub(super) fn finished(&mut self, c: Control) -> Phase {
        let r = self.req.unwrap_or(Req::LineState);
        match self.check(r, &c.got) {
            Ok(next) => self.req = next,
            Err(e) => return self.fail(format!("{}: {e}", c.name)),
        }
        if self.req.is_none() {
            self.configured_at = Some(self.t);
            return Phase::Configured;
        }
        self.phase
    }

    fn check(&mut self, r: Req, got: &[u8]) -> Result<Option<Req>, String> {
        Ok(Some(match r {
            Req::Device8 => {
                self.dev.mps0 = d::device_head(got)?;
                Req::SetAddress
            }
            Req::SetAddress => {
                self.addr = ADDRESS;
                self.pause_until = self.t + 2 * self.ms;
                Req::Device
            }
            Req::Device => {
                d::device(got, &mut self.dev)?;
                Req::Config9
            }
            Req::Config9 => Req::Config(d::config_head(got)? as u16),
            Req::Config(_) => {
                d::config(got, &mut self.dev)?;
                Req::Lang
            }
            Req::Lang => {
                self.lang = d::langid(got)?;
                Req::Str(0)
            }
            Req::Str(i) => {
                self.string(i, got)?;
                if i + 1 < STRINGS.len() {
                    Req::Str(i + 1)
                } else {
                    Req::SetConfig
                }
            }
            Req::SetConfig => Req::LineCoding,
            Req::LineCoding => Req::LineState,
            Req::LineState => return Ok(None),
        }))
    }

    fn string(&mut self, i: usize, got: &[u8]) -> Result<(), String> {
        let (field, want) = STRINGS[i.min(2)];
        let s = d::string(got, self.dev.strings[i.min(2)])?;
        if s != want {
            return Err(format!("{field} is {s:?}, the firmware defines {want:?}"));
        }
        self.strings.push(s);
        Ok(())
    }
}
