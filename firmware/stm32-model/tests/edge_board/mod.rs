//! TIM3, TIM5 and TIM11 as the firmware's edge times use them, on one clock:
//! TIM3 and TIM5 the event-driven `chip::gptimer` (TIM3's TRGO routed to
//! TIM5 through the ITR table), TIM11 the cycle-exact `Mcu`'s, A and B on
//! TIM3's inputs and in GPIOA_IDR. Each bus access takes `ACCESS` cycles.
#![allow(dead_code)]

use polyturn_firmware::edgetime::{self, program, GPIOA_IDR, TIM3, TIM5};
use polyturn_firmware::regs::{apply, Bus};
use polyturn_stm32_model::addr::off;
use polyturn_stm32_model::chip::gptimer::{trigger, GpTimer};
use polyturn_stm32_model::{EncoderCapture, Mcu, Params};

pub const HZ: u64 = 96_000_000;
/// CK_INT cycles per bus access (an APB1 read: two PCLK1 cycles at least).
pub const ACCESS: u64 = 4;

pub struct Board {
    pub now: u64,
    pub mcu: Mcu,
    pub tim3: GpTimer,
    pub tim5: GpTimer,
    /// (A, B)
    pub pins: (bool, bool),
}

impl Board {
    /// Reset, then what embassy sets up: its time driver on TIM5 (gp16.rs:
    /// PSC = 96 MHz / 1 MHz − 1, ARR = 0xFFFF, UG with URS so no UIF,
    /// CCR1 = 0x8000, UIE and CC1IE, CEN) and its Qei on TIM3 (CC1S = CC2S =
    /// 01, CC1E, CC2E, SMS = 011, ARR, CEN); then the firmware's
    /// `program::CONFIG`, verbatim.
    pub fn new(capture: EncoderCapture) -> Board {
        let mut b = Board::embassy(capture);
        apply(&program::CONFIG, &mut b).unwrap();
        b
    }

    /// What embassy leaves, before the firmware's configuration.
    pub fn embassy(capture: EncoderCapture) -> Board {
        let mut tim3 = GpTimer::new(16, 4);
        tim3.set_encoder_capture(capture);
        let mut b =
            Board { now: 0, mcu: Mcu::new(Params::default()), tim3, tim5: GpTimer::new(32, 4), pins: (false, false) };
        for (a, v) in [
            (off::PSC, 95),
            (off::ARR, 0xFFFF),
            (off::CR1, 4),
            (off::EGR, 1),
            (off::CR1, 0),
            (off::CCR1, 0x8000),
            (off::DIER, 0b11),
            (off::CR1, 1),
        ] {
            b.write(TIM5 + a, v);
        }
        for (a, v) in [(off::CCMR1, 0x0101), (off::CCER, 0x0011), (off::SMCR, 3), (off::ARR, 0xFFFF), (off::CR1, 1)] {
            b.write(TIM3 + a, v);
        }
        b
    }

    /// Every model brought to cycle `t`.
    pub fn run_to(&mut self, t: u64) {
        self.now = self.now.max(t);
        self.tim5.advance(self.now, HZ, HZ);
        self.mcu.run_until(self.now);
    }

    /// A and B take new levels at cycle `t` (one of them changes).
    pub fn drive(&mut self, t: u64, a: bool, b: bool) {
        self.run_to(t);
        self.pins = (a, b);
        self.tim3.inputs([a, b, false]);
        trigger::route("TIM3", &mut self.tim3, &mut [("TIM5", &mut self.tim5)]);
    }

    pub fn stamp_now(&mut self) -> u16 {
        self.tim5.read(off::CNT) as u16
    }
}

/// A's and B's levels at count `c` (table 53 counting up: A rises first).
pub fn levels(c: i64) -> (bool, bool) {
    let s = c.rem_euclid(4);
    (s == 1 || s == 2, s >= 2)
}

impl Bus for Board {
    fn write(&mut self, a: u32, v: u32) {
        self.run_to(self.now + ACCESS);
        match a {
            _ if (TIM3..TIM3 + 0x400).contains(&a) => self.tim3.write(a - TIM3, v, u32::MAX),
            _ if (TIM5..TIM5 + 0x400).contains(&a) => self.tim5.write(a - TIM5, v, u32::MAX),
            _ => self.mcu.write(a, v),
        }
    }
    fn read(&mut self, a: u32) -> u32 {
        self.run_to(self.now + ACCESS);
        match a {
            GPIOA_IDR => (self.pins.0 as u32) << edgetime::A_PIN | (self.pins.1 as u32) << edgetime::B_PIN,
            _ if (TIM3..TIM3 + 0x400).contains(&a) => self.tim3.read(a - TIM3),
            _ if (TIM5..TIM5 + 0x400).contains(&a) => self.tim5.read(a - TIM5),
            _ => self.mcu.read(a),
        }
    }
    fn delay(&mut self, cycles: u32) {
        self.run_to(self.now + cycles as u64);
    }
}
