//! What a CPU load or store to a peripheral costs beyond the core's own cycles
//! (which `cycles::timing` counts at zero wait states), by the bus it crosses.
//!
//! - The bus matrix (RM0383 §2.1, Figure 1) takes the Cortex-M4's S-bus to
//!   AHB1 (GPIO, RCC, the flash interface, DMA), AHB2 (USB OTG FS) and, through
//!   the AHB/APB bridges (§2.1.5: "full synchronous connections"), to APB1
//!   (TIM2-5, IWDG, PWR; PCLK1 = HCLK / PPRE1) and APB2 (TIM1, TIM9-11,
//!   SYSCFG, EXTI; PCLK2 = HCLK / PPRE2) (§2.3, Table 1, memory map).
//! - An APB transfer takes two PCLK cycles at least, its setup and its access
//!   phase (AMBA 3 APB protocol, ARM IHI 0024C §3.1-3.2); the bridge waits for
//!   a PCLK edge to start it (up to one PCLK period less a cycle) and hands the
//!   result back on HCLK. The model takes a read as the two PCLK cycles and the
//!   bridge's return; the bound adds the wait for the edge and an arbitration
//!   cycle at the matrix, and takes every write as stalling (the write buffer
//!   full: ARMv7-M's Device memory may buffer a write, which the model credits
//!   with half the transfer).
//! - The core's private bus (0xE000_0000: NVIC, SCB, DWT) is not behind the
//!   matrix: no wait.
//!
//! DMA2, on the same matrix, can hold a slave the CPU wants for one transfer
//! at a time (round-robin arbitration, §2.1.6): that is bounded apart, from
//! the transfers the DMA made during a run (`meter`).

use super::Cost;

/// The bus a peripheral address is on (RM0383 §2.3, Table 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bus {
    Apb1,
    Apb2,
    Ahb1,
    Ahb2,
    Private,
}

pub fn bus_of(addr: u32) -> Bus {
    match addr {
        0x4000_0000..=0x4000_FFFF => Bus::Apb1,
        0x4001_0000..=0x4001_FFFF => Bus::Apb2,
        0x4002_0000..=0x4007_FFFF => Bus::Ahb1,
        0x5000_0000..=0x5006_0BFF => Bus::Ahb2,
        _ => Bus::Private,
    }
}

/// Wait cycles of one access on `bus`, `prescaler` = HCLK / PCLK of an APB.
pub fn access(bus: Bus, prescaler: u64, write: bool) -> Cost {
    let k = prescaler.max(1) as u32;
    match bus {
        // two PCLK cycles and the return on HCLK, less the cycle the core
        // counts; in the bound, the wait for PCLK's edge and arbitration too
        Bus::Apb1 | Bus::Apb2 => {
            let transfer = 2 * k;
            let model = if write { transfer / 2 } else { transfer };
            Cost { model, bound: transfer + (k - 1) + 1 }
        }
        // through the matrix without a bridge: no wait, arbitration in the bound
        Bus::Ahb1 | Bus::Ahb2 => Cost { model: 0, bound: 1 },
        Bus::Private => Cost::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_boards_peripherals_sit_on_their_buses() {
        assert_eq!(bus_of(0x4001_0000), Bus::Apb2, "TIM1");
        assert_eq!(bus_of(0x4001_4800), Bus::Apb2, "TIM11");
        assert_eq!(bus_of(0x4000_0400), Bus::Apb1, "TIM3");
        assert_eq!(bus_of(0x4000_0C00), Bus::Apb1, "TIM5");
        assert_eq!(bus_of(0x4002_0400), Bus::Ahb1, "GPIOB");
        assert_eq!(bus_of(0x4002_6400), Bus::Ahb1, "DMA2");
        assert_eq!(bus_of(0x5000_0000), Bus::Ahb2, "USB OTG FS");
        assert_eq!(bus_of(0xE000_E100), Bus::Private, "NVIC");
    }

    #[test]
    fn apb1_at_half_hclk_costs_twice_apb2_and_the_bound_more() {
        let (a1, a2) = (access(Bus::Apb1, 2, false), access(Bus::Apb2, 1, false));
        assert_eq!(a2, Cost { model: 2, bound: 3 });
        assert_eq!(a1, Cost { model: 4, bound: 6 });
        assert!(access(Bus::Apb1, 2, true).model < a1.model, "a buffered write");
        assert_eq!(access(Bus::Apb1, 2, true).bound, a1.bound, "the bound buffers nothing");
        assert_eq!(access(Bus::Private, 1, false), Cost::default());
    }
}
