//! The emulator's clock in the cycles an STM32F411 spends: two figures, the
//! MODEL's (what silicon most likely spends; the peripherals run on it) and
//! the BOUND's (what silicon cannot exceed: every unknown at its worst).
//!
//! A translated block's cost at zero wait states is static (`cycles::timing`,
//! the Cortex-M4 TRM's Table 3-1 and load/store rules) and cached; what depends
//! on the run is counted as it runs:
//! - the pipeline refill of a taken branch: a block that does not start where
//!   the last one ended was branched to;
//! - instruction fetches and literal loads through the flash's ART
//!   accelerator (`art`), the bound's from a cache flushed at every exception
//!   entry and return and at every section that masks the tick (a cold cache:
//!   anything may have run just before);
//! - SDIV/UDIV by their operands (a hook at each);
//! - exception entry, return, tail-chain and late arrival (`exception`);
//! - peripheral accesses by bus (`bus`), and in the bound DMA2's transfers,
//!   each of which can hold the CPU off a slave it shares for its length.

pub mod art;
pub mod bus;
pub mod exception;
pub mod profile;

use crate::cycles::insn::{Insn, Op};
use crate::cycles::program::Program;
use crate::cycles::timing;
pub use crate::cycles::timing::Cost;
use art::{line_of, Acr, Art};
use std::collections::HashMap;
use std::rc::Rc;

/// The address a load reads from a literal pool, if it is one.
fn literal(i: &Insn) -> Option<u32> {
    match i.op {
        Op::Single { literal, .. } | Op::Double { literal } => literal,
        _ => None,
    }
}

/// What the pairing rules give the block's first instruction after `prev`
/// (the instruction that ran just before), over the static cost that takes
/// its predecessor as unknown: (model, bound), each possibly negative.
fn across(prev: &Insn, first: &Insn) -> (i64, i64) {
    let one = std::slice::from_ref(first);
    let (after, alone) = (timing::block_cost_after(Some(prev), one), timing::block_cost(one));
    (after.model as i64 - alone.model as i64, after.bound as i64 - alone.bound as i64)
}

/// What runs first after an exception's entry or return: no data
/// processing before it, so no address interlock (a hint stands in).
const AFTER_EXCEPTION: Insn =
    Insn { addr: 0, size: 2, op: Op::Hint, reads: 0, writes: 0, addr_regs: 0, conditional: false };

/// Where an instruction is fetched from.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Fetch {
    /// the flash, through the ART accelerator (its alias at 0 too, while
    /// SYSCFG maps it there: RM0383 §2.4, §7.2.1)
    Flash,
    /// the SRAM, at 0 while SYSCFG maps it there, on the I-bus at no wait
    /// state (§2.1.1, §2.3.1): the data it reads and writes meets the fetch
    /// at the SRAM's one port (the bus matrix's round-robin, §2.1.6), which
    /// the bound takes as a cycle lost each time
    Sram,
}

fn fetch_from(addr: u32, sram_at_zero: bool) -> Fetch {
    match addr {
        0..=0x0001_FFFF if sram_at_zero => Fetch::Sram,
        0x2000_0000..=0x2001_FFFF => Fetch::Sram,
        _ => Fetch::Flash,
    }
}

/// Words a memory instruction moves over the bus.
fn beats(i: &Insn) -> u32 {
    match i.op {
        Op::Single { .. } => 1,
        Op::Double { .. } => 2,
        Op::Multiple { regs } => regs as u32,
        Op::FpMem { words } => words as u32,
        _ => 0,
    }
}

/// A block's static facts, worked out once.
struct Block {
    /// cycles at zero wait states, the refill of a taken branch at its end excluded
    body: Cost,
    /// where each instruction starts, in cycles from the block's start
    starts: Vec<(u32, Cost)>,
    /// flash lines the block fetches from, each at its first instruction, and
    /// the literal loads' lines, in the order they are met (`true`: a literal)
    reads: Vec<(u32, Cost, bool)>,
    /// the block's first instruction (its pairing with the one before), its
    /// last (its refill if the next block is not the fall-through), and the
    /// fall-through's address
    first: Option<Insn>,
    last: Option<Insn>,
    end: u32,
}

impl Block {
    fn new(insns: &[Insn], addr: u32, size: u32, sram_at_zero: bool) -> Block {
        let mut starts = Vec::with_capacity(insns.len());
        let mut reads = Vec::new();
        let mut line = None;
        let from = fetch_from(addr, sram_at_zero);
        for (i, insn) in insns.iter().enumerate() {
            let at = if i == 0 { Cost::default() } else { timing::block_cost(&insns[..i]) };
            starts.push((insn.addr, at));
            if from == Fetch::Flash {
                for l in [line_of(insn.addr), line_of(insn.addr + insn.size as u32 - 1)] {
                    if line != Some(l) {
                        reads.push((l, at, false));
                        line = Some(l);
                    }
                }
            }
            if let Some(lit) = literal(insn).filter(|&a| fetch_from(a, sram_at_zero) == Fetch::Flash) {
                reads.push((line_of(lit), at, true));
            }
        }
        let mut body = timing::block_cost(insns);
        if from == Fetch::Sram {
            body.bound += insns.iter().map(beats).sum::<u32>();
        }
        Block { body, starts, reads, first: insns.first().copied(), last: insns.last().copied(), end: addr + size }
    }
}

/// The two clocks' running parts: the flash model for each, the last block
/// (to see a taken branch), and what the last exception event left.
pub struct Meter {
    program: Rc<Program>,
    blocks: HashMap<(u32, u32), Rc<Block>>,
    model: Art,
    bound: Art,
    prev: Option<Rc<Block>>,
    last: exception::Last,
    /// a return's cost, held until the next instruction runs (a tail-chain
    /// replaces it)
    returning: bool,
    /// blocks run whose instructions the program does not list
    pub unlisted: u64,
    /// SYSCFG maps the SRAM at 0 (`Machine::remap`)
    sram_at_zero: bool,
}

impl Meter {
    pub fn new(program: Rc<Program>) -> Meter {
        Meter {
            program,
            blocks: HashMap::new(),
            model: Art::model(),
            bound: Art::bound(),
            prev: None,
            last: exception::Last::Running,
            returning: false,
            unlisted: 0,
            sram_at_zero: false,
        }
    }

    /// FLASH_ACR as the image last wrote it (§3.8.1).
    pub fn set_acr(&mut self, acr: u32) {
        let acr = if std::env::var_os("POLYTURN_EMU_ZERO_WAIT").is_some() { acr & !0xF } else { acr };
        self.model.acr = Acr::from_reg(acr);
        self.bound.acr = Acr::from_reg(acr);
    }

    /// The block of `size` bytes at `addr` starts at model cycle `now` and
    /// bound cycle `bound`: (what comes before its first instruction, its
    /// instructions). Before: a held return, the refill of the branch that
    /// led here. The block: its static cost and its flash waits.
    pub fn block(&mut self, addr: u32, size: u32, now: u64, bound: u64) -> (Cost, Cost) {
        let b = self.static_block(addr, size);
        let mut lead = Cost::default();
        if std::mem::take(&mut self.returning) {
            lead += Cost { model: exception::RETURN, bound: exception::RETURN };
            if self.sram_at_zero {
                // the frame's eight words come back from the SRAM the
                // return's target is fetched from, as at entry
                lead.bound += 8;
            }
        }
        let prev = self.prev.take();
        if let Some(last) = prev.as_ref().filter(|p| p.end != addr).and_then(|p| p.last) {
            let size = b.first.map_or(2, |i| i.size);
            lead += timing::refill(&last, addr, size);
        }
        // the pairing rules across the boundary (the static cost took the
        // first instruction's predecessor as unknown)
        let before = match &prev {
            Some(p) => p.last,
            None if self.last != exception::Last::Running => Some(AFTER_EXCEPTION),
            None => None,
        };
        let adjust = match (before, b.first) {
            (Some(p), Some(f)) => across(&p, &f),
            _ => (0, 0),
        };
        self.last = exception::Last::Running;
        let (t, tb) = (now + lead.model as u64, bound + lead.bound as u64);
        let mut waits = (0u64, 0u64);
        for &(line, at, literal) in &b.reads {
            let (tm, tbb) = (t + at.model as u64 + waits.0, tb + at.bound as u64 + waits.1);
            if literal {
                waits.0 += self.model.literal(line, tm);
                waits.1 += self.bound.literal(line, tbb);
            } else {
                waits.0 += self.model.fetch(line, tm);
                waits.1 += self.bound.fetch(line, tbb);
            }
        }
        let body = Cost {
            model: (b.body.model as i64 + adjust.0 + waits.0 as i64).max(0) as u32,
            bound: (b.body.bound as i64 + adjust.1 + waits.1 as i64).max(0) as u32,
        };
        self.prev = Some(b);
        (lead, body)
    }

    fn static_block(&mut self, addr: u32, size: u32) -> Rc<Block> {
        if let Some(b) = self.blocks.get(&(addr, size)) {
            return b.clone();
        }
        let insns = self.program.block(addr, size);
        if insns.is_empty() {
            self.unlisted += 1;
        }
        let b = Rc::new(Block::new(insns, addr, size, self.sram_at_zero));
        self.blocks.insert((addr, size), b.clone());
        b
    }

    /// Cycles from the start of the block at `block` to its instruction at
    /// `addr` (static: its flash waits are not split between instructions).
    pub fn offset(&self, block: (u32, u32), addr: u32) -> Cost {
        self.blocks.get(&block).and_then(|b| b.starts.iter().find(|s| s.0 == addr).map(|s| s.1)).unwrap_or_default()
    }

    /// An exception taken: its entry's cost, with its vector's read at
    /// `vector` through each clock's flash model at `now` / `bound` (a read
    /// of a word, as a literal's: it is not a line the CPU executes from).
    pub fn enter(&mut self, vector: u32, now: u64, bound: u64) -> Cost {
        let after = if std::mem::take(&mut self.returning) { exception::Last::Returned } else { self.last };
        self.bound.flush();
        let line = line_of(vector);
        let mut c = exception::entry(after, self.model.literal(line, now), self.bound.literal(line, bound));
        if self.sram_at_zero {
            // the frame's eight words go to the SRAM the handler is fetched
            // from: each may cost the fetch a cycle (`Fetch::Sram`)
            c.bound += 8;
        }
        self.prev = None;
        self.last = exception::Last::Entered;
        c
    }

    /// An exception return: its cost is held for the next instruction (a
    /// tail-chain replaces it).
    pub fn exit(&mut self) {
        self.bound.flush();
        self.prev = None;
        self.returning = true;
        self.last = exception::Last::Returned;
    }

    /// SYSCFG mapped the SRAM at 0 (or the flash again): the blocks there are
    /// other code, timed again.
    pub fn set_sram_at_zero(&mut self, on: bool) {
        self.sram_at_zero = on;
        self.blocks.retain(|&(a, _), _| a >= 0x0008_0000);
        self.prev = None;
    }

    /// A section masking the tick opens: the bound takes its cache as cold.
    pub fn cold(&mut self) {
        self.bound.flush();
    }

    /// Flash misses (instruction, literal) of the model and of the bound.
    pub fn misses(&self) -> [(u64, u64); 2] {
        [self.model.misses, self.bound.misses]
    }
}
