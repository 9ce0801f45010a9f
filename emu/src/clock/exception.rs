//! What taking and leaving an exception costs the Cortex-M4, in CPU cycles:
//! ARM's knowledge article KA16366 ("What is the true interrupt latency of
//! Cortex-M3 and Cortex-M4 for interrupt entry and exit?", quoting the
//! Cortex-M4 TRM's figures), the Cortex-M4 Devices Generic User Guide (ARM DUI
//! 0553A §2.3.7: tail-chaining, late arrival) and J. Yiu, *The Definitive
//! Guide to ARM Cortex-M3 and Cortex-M4 Processors*, 3rd ed., chapter 8
//! (tail-chaining's 6 cycles):
//!
//! - entry: 12 cycles from the request to the handler's first instruction, "a
//!   nine cycle stack push ... on one interface (typically the System
//!   interface) in parallel with a six cycle vector table read and interrupt
//!   handler fetch on other interfaces (typically I-Code)" (KA16366). Here the
//!   stack is in SRAM (System bus) and the vector table in flash (I-Code):
//!   the vector's read may stall through the flash's wait states, which the
//!   stacking hides by three cycles in the model and not at all in the bound.
//!   The handler's first fetch is the flash model's, at its first block.
//! - return: 10 cycles (KA16366; the return target's fetch again the flash's).
//! - tail-chaining, an exception taken at a return without unstacking: 6
//!   cycles in place of the return and a new entry.
//! - late arrival, a more urgent exception during another's stacking: it takes
//!   the stacking already under way and fetches its own vector, a tail-chain's
//!   cost at most.
//! - the FPU's extended frame: reserved, not written, with lazy stacking
//!   (FPCCR.LSPEN, on at reset); the 17 more cycles KA16366 gives are paid only
//!   if a handler uses the FPU, and none of the board's handlers may
//!   (`.ci/callgraph` refuses a floating-point instruction reachable from them).

use super::Cost;

/// Request to the handler's first instruction, zero wait states.
pub const ENTRY: u32 = 12;
/// Return to the interrupted instruction.
pub const RETURN: u32 = 10;
/// A pending exception taken at a return.
pub const TAIL_CHAIN: u32 = 6;
/// Cycles of the stacking that run beside the vector's read (9 against 6).
const VECTOR_SLACK: u64 = 3;

/// An exception taken after `after` (how the last exception event left the
/// core), its vector's read stalling `vector_stall` cycles in the model and
/// `vector_stall_bound` in the bound.
pub fn entry(after: Last, vector_stall: u64, vector_stall_bound: u64) -> Cost {
    let base = match after {
        Last::Running => ENTRY,
        // stacked already (late arrival), or never unstacked (a tail-chain:
        // the meter drops the return it held for the next instruction)
        Last::Entered | Last::Returned => TAIL_CHAIN,
    };
    let model = base as u64 + vector_stall.saturating_sub(VECTOR_SLACK);
    let bound = base as u64 + vector_stall_bound;
    Cost { model: model as u32, bound: bound as u32 }
}

/// The last exception event, with no instruction run since.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Last {
    /// an instruction ran since the last entry or return
    #[default]
    Running,
    Entered,
    Returned,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_costs_twelve_and_its_vector_wait_beyond_the_stackings_slack() {
        assert_eq!(entry(Last::Running, 0, 0), Cost { model: 12, bound: 12 });
        assert_eq!(entry(Last::Running, 3, 7), Cost { model: 12, bound: 19 });
        assert_eq!(entry(Last::Running, 5, 7).model, 14);
    }

    #[test]
    fn a_tail_chain_costs_six_where_an_entry_costs_twelve() {
        assert_eq!(entry(Last::Returned, 0, 0).model, 6);
        assert_eq!(entry(Last::Running, 0, 0).model, 12);
    }

    #[test]
    fn a_late_arrival_costs_a_vector_fetch_not_a_second_stacking() {
        assert_eq!(entry(Last::Entered, 0, 0).model, TAIL_CHAIN);
    }
}
