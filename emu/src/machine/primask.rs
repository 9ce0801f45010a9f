//! Interrupts-off sections in thread mode: each `cpsid i` (or `msr primask, rN`
//! with 1) to the `cpsie i` (or `msr` with 0) that ends it, timed on both of
//! the emulator's clocks (`clock`: the model's cycles and the bound's).
//! Sections begun while the tick's interrupt is enabled are the ones that can
//! delay it (app/cs.rs keeps logging and embassy off PRIMASK).

use crate::chip::Chip;
use crate::machine::Machine;
use unicorn_engine::{RegisterARM as R, Unicorn};

pub fn hooks(m: &mut Machine) -> Result<(), String> {
    let ins = &m.image.insns;
    let sites: Vec<(u32, Option<bool>)> = ins
        .cpsid
        .iter()
        .map(|&a| (a, Some(true)))
        .chain(ins.cpsie.iter().map(|&a| (a, Some(false))))
        .chain(ins.msr_primask.iter().map(|&a| (a, None)))
        .collect();
    for (a, value) in sites {
        m.uc.add_code_hook(a as u64, a as u64, move |uc, addr, _| at(uc, addr as u32, value))
            .map_err(|e| format!("unicorn: {e:?}"))?;
    }
    for &a in &m.image.insns.msr_basepri {
        m.uc.add_code_hook(a as u64, a as u64, |uc, addr, _| basepri(uc, addr as u32))
            .map_err(|e| format!("unicorn: {e:?}"))?;
    }
    Ok(())
}

/// `msr basepri, rN` (or basepri_max) about to run: an interrupt it unmasks is
/// taken right after it (PM0214 §2.1.3), so the run stops at this block's end.
fn basepri(uc: &mut Unicorn<Chip>, addr: u32) {
    let value = msr_source(uc, addr);
    let primask = uc.reg_read(R::PRIMASK).unwrap_or(0) & 1 == 1;
    let current = uc.reg_read(R::BASEPRI).unwrap_or(0) as u32;
    let next = crate::tickmask::next_basepri(current, value, sysm(uc, addr) == SYSM_BASEPRI_MAX);
    let t = time_at(uc, addr);
    crate::tickmask::change(uc, t, addr, primask, next);
    if uc.get_data().deliverable(primask, next).is_some() {
        uc.get_data_mut().deadline = 0;
    }
}

/// SYSm of BASEPRI_MAX (ARMv7-M ARM B5.1.1): `msr basepri_max` rather than `basepri`.
const SYSM_BASEPRI_MAX: u16 = 0x12;

/// The special register an `msr` at `addr` writes: SYSm, the low byte of the T1
/// encoding's second halfword (ARMv7-M ARM B5.2.3).
fn sysm(uc: &Unicorn<Chip>, addr: u32) -> u16 {
    halfword(uc, addr + 2) & 0xFF
}

/// The halfword of code at `addr`, as the CPU fetches it (flash, or SRAM
/// mapped at 0).
fn halfword(uc: &Unicorn<Chip>, addr: u32) -> u16 {
    let mut b = [0u8; 2];
    let _ = uc.mem_read(addr as u64, &mut b);
    u16::from_le_bytes(b)
}

/// Both clocks at the instruction at `addr` of the block running now.
fn time_at(uc: &Unicorn<Chip>, addr: u32) -> (u64, u64) {
    let c = uc.get_data();
    let o = c.meter.offset(c.block, addr);
    (c.blk + o.model as u64, c.blk_bound + o.bound as u64)
}

/// The value an `msr <special>, rN` at `addr` is about to write: its T1
/// encoding (ARMv7-M ARM B5.2.3) has Rn in the first halfword's low nibble.
fn msr_source(uc: &Unicorn<Chip>, addr: u32) -> u32 {
    let hw = halfword(uc, addr);
    uc.reg_read(R::R0 as i32 + (hw & 0xF) as i32).unwrap_or(0) as u32
}

fn at(uc: &mut Unicorn<Chip>, addr: u32, value: Option<bool>) {
    if uc.reg_read(R::IPSR).unwrap_or(0) & 0x1FF != 0 {
        return; // only thread-mode sections are measured
    }
    let primask = uc.reg_read(R::PRIMASK).unwrap_or(0) & 1 == 1;
    let value = value.unwrap_or_else(|| msr_source(uc, addr) & 1 == 1);
    let t = time_at(uc, addr);
    crate::tickmask::change(uc, t, addr, value, uc.reg_read(R::BASEPRI).unwrap_or(0) as u32);
    let c = uc.get_data();
    let tick_on = c.nvic.enabled[crate::svd::irq("TIM1_TRG_COM_TIM11")];
    let deliverable = crate::machine::cpu::deliverable(uc, Some(false)).is_some();
    let lr = uc.reg_read(R::LR).unwrap_or(0) as u32 & !1;
    let c = uc.get_data_mut();
    let log = &mut c.primask;
    match (value, log.is_open()) {
        (true, false) if !primask => log.open(t, (addr, lr), tick_on),
        (false, true) => {
            log.close(t);
            if deliverable {
                c.deadline = 0; // taken as soon as this block ends
            }
        }
        _ => {}
    }
}
