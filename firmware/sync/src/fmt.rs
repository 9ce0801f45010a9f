//! Logging shim (after RMK's `fmt.rs`): defmt on the MCU, nothing on the host,
//! so the core links everywhere without a logger.
#![allow(unused_macros)]

#[cfg(feature = "defmt")]
macro_rules! info {
    ($($t:tt)*) => { ::defmt::info!($($t)*) };
}
#[cfg(not(feature = "defmt"))]
macro_rules! info {
    ($($t:tt)*) => {{}};
}

#[cfg(feature = "defmt")]
macro_rules! warn {
    ($($t:tt)*) => { ::defmt::warn!($($t)*) };
}
#[cfg(not(feature = "defmt"))]
macro_rules! warn {
    ($($t:tt)*) => {{}};
}
