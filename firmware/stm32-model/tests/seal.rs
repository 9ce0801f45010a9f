//! The firmware's boot check of its own image (`polyturn_firmware::seal`)
//! run on the model of the CRC unit (RM0383 §4), of RCC and of the GPIO
//! ports, over flash bytes: a sealed image passes, a changed word is
//! caught; the LEDs it lights are PC13 and PA10.

use polyturn_firmware::regs::Bus;
use polyturn_firmware::seal::*;
use polyturn_stm32_model::chip::crc::{self, Crc};
use polyturn_stm32_model::chip::gpio::{Port, OUTPUT};
use polyturn_stm32_model::chip::nvic::Nvic;
use polyturn_stm32_model::chip::rcc::Rcc;

struct Board {
    flash: Vec<u8>,
    crc: Crc,
    rcc: Rcc,
    gpioa: Port,
    gpioc: Port,
    /// the core's system space (DEMCR, the DWT), and the cycles so far:
    /// ten per access here
    ppb: Nvic,
    now: u64,
}

impl Board {
    fn new(flash: Vec<u8>) -> Board {
        Board {
            flash,
            crc: Crc::default(),
            rcc: Rcc::default(),
            gpioa: Port::new('A'),
            gpioc: Port::new('C'),
            ppb: Nvic::default(),
            now: 0,
        }
    }
}

impl Bus for Board {
    fn write(&mut self, addr: u32, value: u32) {
        self.now += 10;
        match addr {
            0xE000_0000.. => self.ppb.write(addr - 0xE000_0000, value, u32::MAX, self.now),
            0x4002_3000..0x4002_3400 => self.crc.write(addr - CRC_BASE, value, u32::MAX),
            0x4002_3800..0x4002_3C00 => self.rcc.write(addr - 0x4002_3800, value, u32::MAX),
            0x4002_0000..0x4002_0400 => drop(self.gpioa.write(addr - GPIOA, value, u32::MAX, 0)),
            0x4002_0800..0x4002_0C00 => drop(self.gpioc.write(addr - GPIOC, value, u32::MAX, 0)),
            _ => panic!("a write to {addr:#010x}"),
        }
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.now += 10;
        match addr {
            0xE000_0000.. => self.ppb.read(addr - 0xE000_0000, self.now, &[], 0),
            FLASH_BASE..APP_END => {
                let at = (addr - FLASH_BASE) as usize;
                // beyond the bytes: erased flash (RM0383 §3.5.3)
                let b = |i: usize| self.flash.get(at + i).copied().unwrap_or(0xFF);
                u32::from_le_bytes([b(0), b(1), b(2), b(3)])
            }
            0x4002_3000..0x4002_3400 => self.crc.read(addr - CRC_BASE),
            0x4002_3800..0x4002_3C00 => self.rcc.read(addr - 0x4002_3800),
            0x4002_0000..0x4002_0400 => self.gpioa.read(addr - GPIOA),
            0x4002_0800..0x4002_0C00 => self.gpioc.read(addr - GPIOC),
            _ => panic!("a read of {addr:#010x}"),
        }
    }
    fn delay(&mut self, _: u32) {}
}

/// `len` bytes of a made-up image (a multiple of 4), sealed by the model.
fn sealed(len: usize) -> Vec<u8> {
    let mut b: Vec<u8> = (0..len).map(|i| (i.wrapping_mul(131) ^ (i >> 7)) as u8).collect();
    let crc = crc::of_words(b.chunks(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])));
    for w in [MAGIC, len as u32, crc] {
        b.extend_from_slice(&w.to_le_bytes());
    }
    b
}

#[test]
fn the_crc_unit_passes_a_sealed_image_and_catches_any_changed_word() {
    let len = 4096;
    assert_eq!(verify(&mut Board::new(sealed(len)), FLASH_BASE + len as u32), Ok(()));
    for at in [0, 5, 0x197, 2000, len - 1] {
        let mut b = sealed(len);
        b[at] ^= 0x40;
        let r = verify(&mut Board::new(b), FLASH_BASE + len as u32);
        assert!(matches!(r, Err(Damage::Crc { .. })), "byte {at}: {r:?}");
    }
    // the clock the check turned on is off again: AHB1ENR as reset left it
    let mut board = Board::new(sealed(len));
    verify(&mut board, FLASH_BASE + len as u32).unwrap();
    assert_eq!(board.rcc.read(0x30), 0);
}

#[test]
fn the_damaged_images_leds_are_pc13_low_and_pa10_high_when_lit() {
    let mut board = Board::new(Vec::new());
    led_setup(&mut board);
    assert_eq!((board.gpioc.field(0, 13), board.gpioa.field(0, 10)), (OUTPUT, OUTPUT));
    assert_eq!(board.gpioa.field(0, 13), 2, "SWD's PA13 still in AF");
    assert_eq!((board.gpioc.level(13), board.gpioa.level(10)), (true, false), "unlit");
    led_on(&mut board, true);
    assert_eq!((board.gpioc.level(13), board.gpioa.level(10)), (false, true), "lit");
    // no other pin of either port is an output
    for (port, led) in [(&board.gpioa, 10), (&board.gpioc, 13)] {
        assert!((0..16).filter(|&p| p != led).all(|p| port.field(0, p) != OUTPUT));
    }
}

#[test]
fn an_image_cut_short_does_not_run_on_a_board_with_no_debugger() {
    let len = 4096;
    let mut board = Board::new(sealed(len)[..2000].to_vec());
    let damage = verify(&mut board, FLASH_BASE + len as u32).unwrap_err();
    assert_eq!(damage, Damage::Unsealed);
    assert!(!probes_own(&mut board, damage), "DHCSR's C_DEBUGEN is clear");
}

#[test]
fn the_damaged_lights_steps_are_timed_by_the_cycle_counter() {
    let mut board = Board::new(Vec::new());
    let start = led_setup(&mut board);
    let mut at = start;
    for _ in 0..3 {
        at = wait(&mut board, at, 16_000);
    }
    assert_eq!(at, start + 48_000);
    // the counter ran from when led_setup started it: past the steps, by
    // less than one read
    let now = board.ppb.read(0x1004, board.now, &[], 0);
    assert!((48_000..48_000 + 20).contains(&now.wrapping_sub(start)), "{}", now.wrapping_sub(start));
}

// The seal's peripheral addresses and bits are `polyturn_regs`', checked
// against ST's SVD there; the core's are the model's.
#[test]
fn the_seals_core_registers_are_the_models() {
    // the core's registers: the model's addresses (ARMv7-M ARM C1.6.5, C1.8)
    use polyturn_stm32_model::chip::nvic;
    let ppb = |off: u32| 0xE000_0000 + off;
    assert_eq!((DEMCR, DWT_CTRL, DWT_CYCCNT), (ppb(nvic::DEMCR), ppb(nvic::DWT_CTRL), ppb(nvic::DWT_CYCCNT)));
    assert_eq!(DHCSR, ppb(nvic::DHCSR));
}
