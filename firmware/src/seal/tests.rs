//! The boot check's accesses, on a bus that records them. The CRC it
//! computes is checked against the model of the CRC unit in
//! `firmware/stm32-model/tests/seal.rs` (and every mutant of a sealed
//! image in `host-sim/src/flash/seal.rs`'s tests).

use super::*;

/// Flash words from FLASH_BASE, registers as plain words; a "CRC" that
/// only XORs the words (the real unit is the model's).
#[derive(Default)]
struct Rec {
    flash: Vec<u32>,
    regs: std::collections::BTreeMap<u32, u32>,
    log: Vec<(char, u32, u32)>,
}

impl Bus for Rec {
    fn write(&mut self, addr: u32, value: u32) {
        self.log.push(('w', addr, value));
        let v = match addr {
            CRC_DR => self.regs.get(&CRC_DR).copied().unwrap_or(0) ^ value,
            CRC_CR if value & CR_RESET != 0 => {
                self.regs.insert(CRC_DR, 0xFFFF_FFFF);
                return;
            }
            _ => value,
        };
        self.regs.insert(addr, v);
    }
    fn read(&mut self, addr: u32) -> u32 {
        if addr == DWT_CYCCNT {
            // a counter that runs 1000 cycles a read
            let c = self.regs.entry(addr).or_insert(0);
            *c = c.wrapping_add(1000);
        }
        let v = if (FLASH_BASE..APP_END).contains(&addr) {
            self.flash.get(((addr - FLASH_BASE) / 4) as usize).copied().unwrap_or(u32::MAX)
        } else {
            self.regs.get(&addr).copied().unwrap_or(0)
        };
        self.log.push(('r', addr, v));
        v
    }
    fn delay(&mut self, _: u32) {}
}

fn sealed(words: &[u32]) -> Rec {
    let crc = words.iter().fold(0xFFFF_FFFF, |c, w| c ^ w);
    let mut flash = words.to_vec();
    flash.extend([MAGIC, 4 * words.len() as u32, crc]);
    Rec { flash, regs: [(RCC_AHB1ENR, 1 << 20)].into(), log: Vec::new() }
}

fn end_of(words: &[u32]) -> u32 {
    FLASH_BASE + 4 * words.len() as u32
}

#[test]
fn a_whole_image_passes_with_the_crc_units_clock_as_it_was() {
    let words = [0x2002_0000, 0x0800_0199, 7, 8, 9];
    let mut bus = sealed(&words);
    assert_eq!(verify(&mut bus, end_of(&words)), Ok(()));
    // every word once into DR, after a RESET, with the clock on
    let fed: Vec<u32> = bus.log.iter().filter(|a| a.0 == 'w' && a.1 == CRC_DR).map(|a| a.2).collect();
    assert_eq!(fed, words);
    let reset = bus.log.iter().position(|a| *a == ('w', CRC_CR, CR_RESET)).unwrap();
    let first = bus.log.iter().position(|a| a.1 == CRC_DR).unwrap();
    let on = bus.log.iter().position(|a| *a == ('w', RCC_AHB1ENR, 1 << 20 | CRCEN)).unwrap();
    assert!(on < reset && reset < first);
    assert_eq!(bus.regs[&RCC_AHB1ENR], 1 << 20, "AHB1ENR as it was");
}

#[test]
fn each_damage_is_named() {
    let words = [0x2002_0000, 0x0800_0199, 7, 8, 9];
    let end = end_of(&words);
    let mut bus = sealed(&words);
    bus.flash[3] ^= 0x100;
    assert!(matches!(verify(&mut bus, end), Err(Damage::Crc { .. })));
    // cut short: the seal's words read erased
    let mut bus = sealed(&words);
    bus.flash.truncate(5);
    assert_eq!(verify(&mut bus, end), Err(Damage::Unsealed));
    // grown or shifted: other bytes where the seal belongs
    let mut bus = sealed(&words);
    bus.flash[5] = 0x1234_5678;
    assert_eq!(verify(&mut bus, end), Err(Damage::NoSeal));
    let mut bus = sealed(&words);
    bus.flash.truncate(6);
    assert_eq!(verify(&mut bus, end), Err(Damage::Length { sealed: u32::MAX }));
    let mut bus = sealed(&words);
    bus.flash[6] = 16;
    assert_eq!(verify(&mut bus, end), Err(Damage::Length { sealed: 16 }));
}

#[test]
fn an_end_outside_the_image_sectors_reads_nothing() {
    for end in [FLASH_BASE, FLASH_BASE + 2, APP_END - 8, APP_END, 0x2000_0000, 0] {
        let mut bus = sealed(&[1, 2]);
        assert_eq!(verify(&mut bus, end), Err(Damage::End(end)), "{end:#x}");
        assert!(bus.log.is_empty(), "{end:#x}: {:?}", bus.log);
    }
    assert_eq!(verify(&mut sealed(&[1, 2]), APP_END - 12), Err(Damage::Unsealed), "the last place a seal fits");
}

#[test]
fn the_leds_become_outputs_unlit_and_nothing_else_changes() {
    let mut bus = Rec::default();
    bus.regs.insert(GPIOA + MODER, 0xA800_0000);
    bus.regs.insert(RCC_AHB1ENR, CRCEN);
    let at = led_setup(&mut bus);
    assert_eq!(at, 1000, "the counter's count, read after it was started");
    assert_eq!((bus.regs[&DEMCR], bus.regs[&DWT_CTRL]), (TRCENA, CYCCNTENA));
    assert_eq!(bus.regs[&(GPIOA + MODER)], 0xA810_0000, "PA10 output, the SWD pins kept");
    assert_eq!(bus.regs[&(GPIOC + MODER)], 1 << 26, "PC13 output");
    assert_eq!(bus.regs[&RCC_AHB1ENR], CRCEN | GPIOAEN | GPIOCEN);
    // unlit before the pins drive: PC13 high (active low), PA10 low
    let first_moder = bus.log.iter().position(|a| a.0 == 'w' && a.1 % 0x400 == MODER).unwrap();
    let lit_writes: Vec<_> =
        bus.log[..first_moder].iter().filter(|a| a.1 % 0x400 == BSRR).map(|a| (a.1, a.2)).collect();
    assert_eq!(lit_writes, vec![(GPIOC + BSRR, 1 << 13), (GPIOA + BSRR, 1 << 26)]);
    bus.log.clear();
    led_on(&mut bus, true);
    assert_eq!(bus.log, vec![('w', GPIOC + BSRR, 1 << 29), ('w', GPIOA + BSRR, 1 << 10)]);
}

#[test]
fn a_wait_ends_once_the_cycles_passed_and_the_next_step_starts_there() {
    let mut bus = Rec::default();
    bus.regs.insert(DWT_CYCCNT, u32::MAX - 2500);
    let from = u32::MAX - 2500;
    // reads give from+1000, +2000, +3000 (across the wrap): done at the third
    assert_eq!(wait(&mut bus, from, 2500), 0xFFFF_FFFF - 2500 + 2500);
    assert_eq!(bus.log.iter().filter(|a| a.1 == DWT_CYCCNT).count(), 3);
    // a counter that never moves: at most `cycles` reads, then on
    let mut stuck = Rec::default();
    struct Still<'a>(&'a mut Rec);
    impl Bus for Still<'_> {
        fn write(&mut self, a: u32, v: u32) {
            self.0.write(a, v)
        }
        fn read(&mut self, a: u32) -> u32 {
            self.0.log.push(('r', a, 0));
            0
        }
        fn delay(&mut self, _: u32) {}
    }
    assert_eq!(wait(&mut Still(&mut stuck), 0, 40), 40);
    assert_eq!(stuck.log.len(), 40);
}

#[test]
fn only_an_unsealed_image_with_a_debugger_attached_runs_unsealed() {
    let mut bus = Rec::default();
    for damage in [Damage::NoSeal, Damage::Length { sealed: 4 }, Damage::Crc { sealed: 1, computed: 2 }, Damage::End(0)]
    {
        bus.regs.insert(DHCSR, C_DEBUGEN);
        assert!(!probes_own(&mut bus, damage), "{damage:?}");
    }
    assert!(probes_own(&mut bus, Damage::Unsealed), "cargo fw-run");
    bus.regs.insert(DHCSR, 0x0003_0000); // S_REGRDY, S_HALT: no C_DEBUGEN
    assert!(!probes_own(&mut bus, Damage::Unsealed), "no debugger");
}
