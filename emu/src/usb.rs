//! The emulated USB host on the other side of `polyturn_stm32_model::chip::otg`:
//! a full-speed host that enumerates the firmware's CDC-ACM console as a real one
//! does (`host`, `control`), checks what the device describes (`descriptors`), then
//! moves console bytes on the bulk endpoints; and the scenario that uses it.

pub mod control;
pub mod descriptors;
pub mod host;
pub mod pty;
pub mod scenario;
