//! Exception entry and return, and the NVIC's choice of what to take (PM0214 §2.3,
//! §4.3). unicorn's M-class core has no NVIC: it only reports a load of EXC_RETURN
//! into the PC (QEMU's EXCP_EXCEPTION_EXIT, interrupt number 8); the rest is here.
//!
//! - Priorities: pre-emption by group priority only when strictly higher than the
//!   execution priority; ties among pending exceptions go to the lowest number.
//! - Level-sensitive lines (§4.3.9) re-pend after return while still asserted.
//! - Entry (§2.3.7): an 8-word frame R0-R3, R12, LR, return address, xPSR (bit 9
//!   records a 4-byte realignment, CCR.STKALIGN = 1); with CONTROL.FPCA the extended
//!   frame (+S0-S15, FPSCR, reserved) and EXC_RETURN bit 4 clear. LR = EXC_RETURN,
//!   IPSR = the exception number, PC from the vector table at VTOR (0 aliases flash).
//! - Return: unstacks the frame EXC_RETURN names, restores IPSR from the stacked xPSR.
//!
//! What each costs in cycles is `clock::exception`'s (the meter counts it here).

use crate::chip::Chip;
use crate::machine::Machine;
use unicorn_engine::{RegisterARM as R, Unicorn};

const FRAME: [R; 6] = [R::R0, R::R1, R::R2, R::R3, R::R12, R::LR];

fn reg(uc: &Unicorn<Chip>, r: R) -> u32 {
    uc.reg_read(r).unwrap_or(0) as u32
}

fn set(uc: &mut Unicorn<Chip>, r: R, v: u32) {
    let _ = uc.reg_write(r, v as u64);
}

fn sreg(n: usize) -> i32 {
    R::S0 as i32 + n as i32
}

/// The exception that pre-empts now, if any.
pub fn deliverable(uc: &Unicorn<Chip>, primask: Option<bool>) -> Option<usize> {
    let pm = primask.unwrap_or(reg(uc, R::PRIMASK) & 1 == 1);
    uc.get_data().deliverable(pm, reg(uc, R::BASEPRI))
}

/// After a bus write (or a pin driven from outside): lines may have changed; if
/// something can now pre-empt, stop at the next block boundary to take it.
pub fn after_write(uc: &mut Unicorn<Chip>) {
    uc.get_data_mut().update_lines();
    if deliverable(uc, None).is_some() {
        uc.get_data_mut().deadline = 0;
    }
}

pub fn take(m: &mut Machine) {
    m.chip().update_lines();
    while let Some(e) = deliverable(&m.uc, None) {
        if !enter(&mut m.uc, e) {
            return;
        }
    }
}

fn enter(uc: &mut Unicorn<Chip>, exc: usize) -> bool {
    let control = reg(uc, R::CONTROL);
    if control & 2 != 0 && uc.get_data().active.is_empty() {
        uc.get_data_mut().fault("thread mode on PSP: not modelled".into());
        return false;
    }
    let fp = control & 4 != 0;
    let sp = reg(uc, R::SP);
    let mut xpsr = reg(uc, R::XPSR) | 1 << 24;
    let mut words: Vec<u32> = FRAME.iter().map(|&r| reg(uc, r)).collect();
    words.extend([reg(uc, R::PC), 0]);
    if fp {
        words.extend((0..16).map(|i| uc.reg_read(sreg(i)).unwrap_or(0) as u32));
        words.extend([reg(uc, R::FPSCR), 0]);
    }
    let size = 4 * words.len() as u32;
    let align = (sp - size) & 4;
    if align != 0 {
        xpsr |= 1 << 9;
    }
    words[7] = xpsr;
    let sp = sp - size - align;
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    if uc.mem_write(sp as u64, &bytes).is_err() {
        uc.get_data_mut().fault(format!("exception {exc}: stack at {sp:#010x} is not RAM"));
        return false;
    }
    set(uc, R::SP, sp);
    let nested = !uc.get_data().active.is_empty();
    let mut exc_return = if nested { 0xFFFF_FFF1 } else { 0xFFFF_FFF9 };
    if fp {
        exc_return &= !0x10;
        set(uc, R::CONTROL, control & !4);
    }
    let c = uc.get_data_mut();
    c.nvic.pending[exc] = false;
    c.active.push(exc);
    *c.entries.entry(exc).or_default() += 1;
    crate::chip::probe::on_enter(c, exc);
    let vtor = c.nvic.vtor();
    // the entry's cycles: stacking, the vector's read (`clock::exception`)
    let cost = c.meter.enter(vtor + 4 * exc as u32, c.now, c.bound);
    c.now += cost.model as u64;
    c.bound += cost.bound as u64;
    set(uc, R::LR, exc_return);
    set(uc, R::XPSR, (xpsr & !0x1FF & !(1 << 9) & !0x0600_FC00) | exc as u32);
    let mut v = [0u8; 4];
    let _ = uc.mem_read((vtor + 4 * exc as u32) as u64, &mut v);
    set(uc, R::PC, u32::from_le_bytes(v) | 1);
    true
}

/// unicorn's interrupt hook: 8 is an exception return; anything else is a fault.
pub fn interrupt(uc: &mut Unicorn<Chip>, intno: u32) {
    if intno == 8 {
        exit(uc, reg(uc, R::PC) | 1);
        return;
    }
    let what = match intno {
        1 => "UsageFault (undefined instruction)",
        2 => "SVC",
        3 => "prefetch abort",
        4 => "data abort",
        7 => "BKPT",
        _ => "exception",
    };
    let pc = reg(uc, R::PC);
    uc.get_data_mut().fault(format!("{what} ({intno}) at {pc:#010x}"));
    let _ = uc.emu_stop();
}

fn exit(uc: &mut Unicorn<Chip>, exc_return: u32) {
    let kind = exc_return & 0xF;
    if uc.get_data().active.is_empty() || ![1, 9, 0xD].contains(&kind) {
        return uc.get_data_mut().fault(format!("bad EXC_RETURN {exc_return:#010x}"));
    }
    if kind == 0xD {
        return uc.get_data_mut().fault("return to PSP: not modelled".into());
    }
    let done = uc.get_data_mut().active.pop().unwrap_or(0);
    let sp = reg(uc, R::MSP);
    let n = if exc_return & 0x10 != 0 { 8 } else { 26 };
    let mut raw = vec![0u8; 4 * n];
    let _ = uc.mem_read(sp as u64, &mut raw);
    let w: Vec<u32> = raw.chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    for (r, v) in FRAME.iter().zip(&w) {
        set(uc, *r, *v);
    }
    // CONTROL.FPCA = NOT EXC_RETURN[4] (ARMv7-M B1.5.8, ExceptionReturn)
    if n == 26 {
        for i in 0..16 {
            let _ = uc.reg_write(sreg(i), w[8 + i] as u64);
        }
        set(uc, R::FPSCR, w[24]);
        set(uc, R::CONTROL, reg(uc, R::CONTROL) | 4);
    } else {
        set(uc, R::CONTROL, reg(uc, R::CONTROL) & !4);
    }
    let xpsr = w[7];
    set(uc, R::SP, sp + 4 * n as u32 + if xpsr >> 9 & 1 == 1 { 4 } else { 0 });
    set(uc, R::XPSR, xpsr & !(1 << 9));
    let back = (xpsr & 0x1FF) as usize;
    let c = uc.get_data_mut();
    if back != c.active.last().copied().unwrap_or(0) {
        let f = format!("return from {done} lands in IPSR {back}, active {:?}", c.active);
        return c.fault(f);
    }
    set(uc, R::PC, w[6] | 1);
    // the return's cycles are the meter's, held for the next instruction
    uc.get_data_mut().meter.exit();
    crate::chip::probe::on_return(uc.get_data_mut(), done);
    after_write(uc); // tail-chain: taken at the next block boundary
}
