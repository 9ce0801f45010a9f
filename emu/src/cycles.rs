//! The static half of the cycle clock: the image's instructions (`insn`, from
//! llvm-objdump's disassembly) and what each costs the Cortex-M4 core at zero
//! wait states (`timing`, from the Cortex-M4 TRM). Pure: no unicorn.

mod decode;
pub mod insn;
mod mnemonic;
mod operands;
pub mod program;
pub mod timing;

#[cfg(test)]
mod image_tests;
#[cfg(test)]
mod insn_tests;
#[cfg(test)]
mod timing_tests;
