//! The descriptors a host checks (USB 2.0 §9.6; CDC 1.2 §5; CDC PSTN §5.3): each
//! error names the descriptor and the field. Parsing is of bytes from the device:
//! bounds are checked, never assumed.

/// What the host keeps from the device and configuration descriptors.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Device {
    pub mps0: usize,
    pub strings: [u8; 3],
    pub config_value: u8,
    /// the CDC communication interface (class requests go to it)
    pub comm: u8,
    pub bulk_in: u8,
    pub bulk_out: u8,
    pub bulk_mps: usize,
}

pub const VID: u16 = 0x16c0;
pub const PID: u16 = 0x27dd;

fn le16(d: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([d.get(i).copied().unwrap_or(0), d.get(i + 1).copied().unwrap_or(0)])
}

fn expect(what: &str, field: &str, got: u32, ok: bool) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(format!("{what}: {field} = {got:#x}"))
    }
}

/// The first 8 bytes of the device descriptor: bLength, bDescriptorType,
/// bMaxPacketSize0 (8, 16, 32 or 64 at full speed, §9.6.1).
pub fn device_head(d: &[u8]) -> Result<usize, String> {
    let w = "device descriptor (8 bytes)";
    expect(w, "length returned", d.len() as u32, d.len() == 8)?;
    expect(w, "bLength", d[0] as u32, d[0] == 18)?;
    expect(w, "bDescriptorType", d[1] as u32, d[1] == 1)?;
    expect(w, "bMaxPacketSize0", d[7] as u32, [8, 16, 32, 64].contains(&d[7]))?;
    Ok(d[7] as usize)
}

/// The whole device descriptor (§9.6.1): this device's VID/PID, strings named,
/// one configuration, and a class either CDC (2) or the IAD composite (EF/02/01).
pub fn device(d: &[u8], dev: &mut Device) -> Result<(), String> {
    let w = "device descriptor";
    expect(w, "length returned", d.len() as u32, d.len() == 18)?;
    device_head(&d[..8]).map_err(|e| e.replace(" (8 bytes)", ""))?;
    let bcd = le16(d, 2);
    expect(w, "bcdUSB", bcd as u32, bcd == 0x0200 || bcd == 0x0210)?;
    let class = (d[4], d[5], d[6]);
    expect(w, "bDeviceClass", d[4] as u32, class == (0xEF, 2, 1) || class == (2, 0, 0))?;
    expect(w, "idVendor", le16(d, 8) as u32, le16(d, 8) == VID)?;
    expect(w, "idProduct", le16(d, 10) as u32, le16(d, 10) == PID)?;
    for (i, f) in ["iManufacturer", "iProduct", "iSerialNumber"].iter().enumerate() {
        expect(w, f, d[14 + i] as u32, d[14 + i] != 0)?;
        dev.strings[i] = d[14 + i];
    }
    expect(w, "bNumConfigurations", d[17] as u32, d[17] == 1)?;
    dev.mps0 = d[7] as usize;
    Ok(())
}

/// The configuration descriptor's first 9 bytes: its wTotalLength.
pub fn config_head(d: &[u8]) -> Result<usize, String> {
    let w = "configuration descriptor (9 bytes)";
    expect(w, "length returned", d.len() as u32, d.len() == 9)?;
    expect(w, "bLength", d[0] as u32, d[0] == 9)?;
    expect(w, "bDescriptorType", d[1] as u32, d[1] == 2)?;
    let total = le16(d, 2) as usize;
    expect(w, "wTotalLength", total as u32, (9..=255).contains(&total))?;
    Ok(total)
}

/// Splits descriptors by bLength; each at least 2 bytes and within `d`.
fn split(d: &[u8]) -> Result<Vec<&[u8]>, String> {
    let (mut out, mut i) = (Vec::new(), 0);
    while i < d.len() {
        let n = d[i] as usize;
        if n < 2 || i + n > d.len() {
            return Err(format!("configuration descriptor: bLength {n} at byte {i} runs past wTotalLength"));
        }
        out.push(&d[i..i + n]);
        i += n;
    }
    Ok(out)
}

/// What the walk over the configuration saw.
#[derive(Default)]
struct Walk {
    interfaces: Vec<(u8, u8, u8)>,
    /// (interface class, bEndpointAddress, bmAttributes, wMaxPacketSize)
    endpoints: Vec<(u8, u8, u8, u16)>,
    /// CDC functional descriptor subtypes, and the union's (control, subordinate)
    functional: Vec<u8>,
    union: Option<(u8, u8)>,
}

fn walk(descs: &[&[u8]]) -> Walk {
    let mut w = Walk::default();
    for d in descs {
        match (d[1], d.len()) {
            (4, 9..) => w.interfaces.push((d[2], d[5], d[6])),
            (5, 7..) => {
                let class = w.interfaces.last().map_or(0, |i| i.1);
                w.endpoints.push((class, d[2], d[3], le16(d, 4)));
            }
            (0x24, 3..) => {
                w.functional.push(d[2]);
                if d[2] == 6 && d.len() >= 5 {
                    w.union = Some((d[3], d[4]));
                }
            }
            _ => {}
        }
    }
    w
}

/// The whole configuration (§9.6.3-§9.6.6; CDC PSTN §5.3): a CDC-ACM function, a
/// communication interface (class 2, subclass 2) with header, ACM and union
/// functional descriptors and an interrupt IN endpoint; a data interface (class
/// 0x0A) with a bulk IN and a bulk OUT endpoint of 8-64 bytes.
pub fn config(d: &[u8], dev: &mut Device) -> Result<(), String> {
    let w = "configuration descriptor";
    config_head(&d[..d.len().min(9)]).map_err(|e| e.replace(" (9 bytes)", ""))?;
    expect(w, "wTotalLength", le16(d, 2) as u32, le16(d, 2) as usize == d.len())?;
    let v = walk(&split(d)?);
    let mut numbers: Vec<u8> = v.interfaces.iter().map(|i| i.0).collect();
    numbers.dedup();
    expect(w, "bNumInterfaces", d[4] as u32, d[4] as usize == numbers.len())?;
    expect(w, "bConfigurationValue", d[5] as u32, d[5] != 0)?;
    let comm = v
        .interfaces
        .iter()
        .find(|i| i.1 == 2 && i.2 == 2)
        .ok_or("no CDC-ACM communication interface (class 2, subclass 2)")?;
    let data = v.interfaces.iter().find(|i| i.1 == 0x0A).ok_or("no CDC data interface (class 0x0A)")?;
    for (sub, name) in [(0, "header"), (2, "ACM"), (6, "union")] {
        if !v.functional.contains(&sub) {
            return Err(format!("{w}: no CDC {name} functional descriptor (bDescriptorSubtype {sub})"));
        }
    }
    let u = v.union.unwrap_or_default();
    expect(w, "union bControlInterface", u.0 as u32, u.0 == comm.0)?;
    expect(w, "union bSubordinateInterface0", u.1 as u32, u.1 == data.0)?;
    let ep = |class: u8, attr: u8, dir_in: bool| {
        v.endpoints.iter().find(|e| e.0 == class && e.2 & 3 == attr && (e.1 & 0x80 != 0) == dir_in)
    };
    ep(2, 3, true).ok_or("no interrupt IN endpoint on the communication interface")?;
    let bin = ep(0x0A, 2, true).ok_or("no bulk IN endpoint on the data interface")?;
    let bout = ep(0x0A, 2, false).ok_or("no bulk OUT endpoint on the data interface")?;
    for e in [bin, bout] {
        expect(w, "bulk wMaxPacketSize", e.3 as u32, [8, 16, 32, 64].contains(&e.3))?;
    }
    dev.config_value = d[5];
    dev.comm = comm.0;
    (dev.bulk_in, dev.bulk_out, dev.bulk_mps) = (bin.1 & 0xF, bout.1 & 0xF, bout.3 as usize);
    Ok(())
}

/// String descriptor 0 (§9.6.7): the first LANGID.
pub fn langid(d: &[u8]) -> Result<u16, String> {
    let w = "string descriptor 0";
    expect(w, "bLength", d.first().copied().unwrap_or(0) as u32, d.len() >= 4 && d[0] as usize == d.len())?;
    expect(w, "bDescriptorType", d[1] as u32, d[1] == 3)?;
    Ok(le16(d, 2))
}

/// A string descriptor (§9.6.7): UTF-16LE text, bLength even and as returned.
pub fn string(d: &[u8], index: u8) -> Result<String, String> {
    let w = format!("string descriptor {index}");
    let n = d.first().copied().unwrap_or(0) as usize;
    expect(&w, "bLength", n as u32, n >= 2 && n == d.len() && n.is_multiple_of(2))?;
    expect(&w, "bDescriptorType", d[1] as u32, d[1] == 3)?;
    let units: Vec<u16> = d[2..].chunks(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
    String::from_utf16(&units).map_err(|_| format!("{w}: not UTF-16"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEV: [u8; 18] = [18, 1, 0x10, 2, 0xEF, 2, 1, 64, 0xc0, 0x16, 0xdd, 0x27, 0, 1, 1, 2, 3, 1];

    #[test]
    fn the_device_descriptor_names_the_bad_field() {
        let mut dev = Device::default();
        assert_eq!(device(&DEV, &mut dev), Ok(()));
        assert_eq!((dev.mps0, dev.strings), (64, [1, 2, 3]));
        let mut bad = DEV;
        bad[10] = 0;
        assert_eq!(device(&bad, &mut dev), Err("device descriptor: idProduct = 0x2700".into()));
        assert!(device(&DEV[..12], &mut dev).unwrap_err().contains("length returned"));
        assert_eq!(device_head(&DEV[..8]), Ok(64));
    }

    #[test]
    fn a_truncated_or_overlong_descriptor_is_an_error_not_a_panic() {
        assert!(split(&[9, 2, 0]).is_err());
        assert!(split(&[0, 2]).is_err());
        assert!(string(&[], 1).is_err());
        assert!(string(&[3, 3, 0], 1).is_err());
        assert_eq!(string(&[6, 3, b'o', 0, b'k', 0], 1), Ok("ok".into()));
        assert!(langid(&[2, 3]).is_err());
        assert!(config(&[9, 2, 9, 0, 0, 1, 0, 0x80, 50], &mut Device::default()).is_err());
    }
}
