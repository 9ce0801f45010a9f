//! Register programs: the register writes the MCU performs, as data. The
//! MCU applies a program verbatim (`apply`, through a five-line `Bus` over
//! volatile pointers); the host runs the same program through a model of
//! the peripheral written from RM0383 (`polyturn-stm32-model`). Used by the
//! step output (`stepgen::program`) and the settings' sector erase
//! (`flashprog`). The programs' words are spelt in `polyturn_regs`: the
//! manual's addresses and fields, which that crate's tests check against
//! ST's SVD (stm32-metapac), and which the model decodes too.

/// One bus operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// a 32-bit write
    Write(u32, u32),
    /// read `addr` until `(value & mask) == 0`, at most `polls` times
    WaitClear { addr: u32, mask: u32, polls: u32 },
    /// `to = from + add`, unless that reaches `limit`; then fails if `flag`
    /// has `mask` set (the tick ended around the copy: too late)
    Sync { from: u32, to: u32, add: u32, limit: u32, flag: u32, mask: u32 },
    /// wait at least this many timer (= CPU) cycles
    Delay(u32),
}

/// The seam: the MCU's volatile accesses, or the host's model.
pub trait Bus {
    fn write(&mut self, addr: u32, value: u32);
    fn read(&mut self, addr: u32) -> u32;
    fn delay(&mut self, cycles: u32);
    /// The writes before it done before any access after it (a DMB on the
    /// MCU: ARMv7-M does not order a store to RAM before a later load from
    /// a peripheral, and a buffered store could reach the RAM after the
    /// DMA's read that the load was to rule out). Nothing on a model.
    fn barrier(&mut self) {}
}

/// Applies `ops` in order; `Err(i)` if op `i` could not complete (the rest
/// is not applied).
pub fn apply(ops: &[Op], bus: &mut impl Bus) -> Result<(), usize> {
    for (i, op) in ops.iter().enumerate() {
        match *op {
            Op::Write(addr, value) => bus.write(addr, value),
            Op::WaitClear { addr, mask, polls } => {
                if !(0..polls).any(|_| bus.read(addr) & mask == 0) {
                    return Err(i);
                }
            }
            Op::Sync { from, to, add, limit, flag, mask } => {
                // read and write back to back: their distance is `add`
                let at = bus.read(from).wrapping_add(add);
                if at >= limit {
                    return Err(i);
                }
                bus.write(to, at);
                if bus.read(flag) & mask != 0 {
                    return Err(i);
                }
            }
            Op::Delay(cycles) => bus.delay(cycles),
        }
    }
    Ok(())
}
