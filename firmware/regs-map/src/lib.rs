//! The STM32F411's register addresses ([`addr`]) and bit fields ([`bits`]),
//! named as in the reference manual RM0383, each with its section: the one
//! table that the firmware's register programs (`polyturn-firmware`) and the
//! model of the chip they run on in the tests (`polyturn-stm32-model`) are
//! both written in. Every address and field is checked against ST's SVD as
//! stm32-metapac carries it, here (`tests/metapac_*.rs`): a wrong bit fails a
//! test, not a board.
//!
//! No dependencies and `no_std`: the firmware links it.
#![no_std]

pub mod addr;
pub mod bits;
