//! Stand-ins for flashing: a fake ROM bootloader (`fake`) and images built
//! for tests (`testkit`), over the product's flash layout
//! (`polyturn_host::flash`).

pub mod fake;
pub mod testkit;
