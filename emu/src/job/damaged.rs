//! Scenario (k): a damaged image does not run. The real release image is
//! flashed damaged three ways, the ways a flash goes wrong: its last
//! 11.8 KB erased (a write cut short), a byte of its vector table changed
//! (an unused interrupt's entry, so that the CPU still starts), a byte of
//! its `.rodata` changed. Each boots; the image's own check
//! (`polyturn_firmware::seal`, with the CRC unit) must stop it: no pin but
//! the two LEDs made an output (STEP, ENABLE, the ESC and USB's D+/D- as
//! reset left them), TIM1 stopped, the watchdog not started, and the LEDs
//! showing `led::damaged` step by step over a whole frame.

use crate::checks::Report;
use crate::image::Image;
use crate::machine::Machine;
use polyturn_firmware::led;
use polyturn_stm32_model::addr::TIM1_CR1;
use polyturn_stm32_model::chip::gpio::MODER;
use polyturn_stm32_model::Params;
use std::rc::Rc;

/// GPIOx_MODER as reset leaves it (RM0383 §8.4.1: port A's SWD pins, port
/// B's JTAG pins in AF) with PA10 and PC13 made outputs (01).
const MODER_DAMAGED: [u32; 3] = [0xA800_0000 | 1 << 20, 0x0000_0280, 1 << 26];

/// The damages: name, and the flash bytes written over the image.
fn damages(image: &Image) -> Vec<(&'static str, (u32, Vec<u8>))> {
    let (base, bytes) = (image.segments[0].0, &image.segments[0].1);
    let flip = |at: usize| (base + at as u32, vec![bytes[at] ^ 0x5A]);
    let cut = bytes.len().saturating_sub(11_800);
    vec![
        ("its last 11.8 KB erased", (base + cut as u32, vec![0xFF; bytes.len() - cut])),
        // entry 60 of the table: an interrupt the firmware leaves alone
        ("a vector-table byte changed", flip(4 * 60 + 1)),
        ("a .rodata byte changed", flip(bytes.len() - 4096)),
    ]
}

pub fn run(image: &Rc<Image>, r: &mut Report) -> Result<u64, String> {
    let mut total = 0;
    for (name, damage) in damages(image) {
        let mut m = Machine::new(image.clone(), Params::default(), &[damage])?;
        let (seen, text) = watch(&mut m);
        total += m.chip().now;
        r.line(seen, "damaged-image", &format!("{name}: {text}"));
    }
    Ok(total)
}

/// Runs one frame of the damaged light and a step more, sampling the LEDs
/// in the middle of each step; whether all is as it must be, and what was.
fn watch(m: &mut Machine) -> (bool, String) {
    let sysclk = m.chip().sysclk();
    let step = sysclk * led::DAMAGED_STEP_MS as u64 / 1000;
    // the check runs at boot: a few ms at the HSI; a second is plenty
    let ms = sysclk / 1000;
    let mut from = None;
    for _ in 0..1000 {
        m.run(ms);
        from = m.chip().gpio[2].output_since[13];
        if from.is_some() || !m.chip().faults.is_empty() {
            break;
        }
    }
    let Some(from) = from else {
        let faults = crate::checks::faults(m);
        return (false, format!("PC13 never became an output; faults: {faults}"));
    };
    let now = m.chip().now;
    m.run((from + step / 2).saturating_sub(now));
    let mut wrong = Vec::new();
    for k in 0..(led::DAMAGED_FRAME_MS / led::DAMAGED_STEP_MS) {
        let c = m.chip();
        let (pc13, pa10) = (c.gpio[2].pin_out(13), c.gpio[0].pin_out(10));
        let want = led::damaged(k * led::DAMAGED_STEP_MS);
        if (pc13, pa10) != (Some(!want), Some(want)) {
            wrong.push(format!("at {} ms PC13 {pc13:?} PA10 {pa10:?}", k * led::DAMAGED_STEP_MS));
        }
        m.run(step);
    }
    let c = m.chip();
    let moder: Vec<u32> = (0..3).map(|p| c.gpio[p].read(MODER)).collect();
    let tim1 = c.mcu.read(TIM1_CR1) & 1;
    let dog = c.iwdg.started_at().is_some();
    let clean = c.faults.is_empty();
    let still = moder == MODER_DAMAGED && tim1 == 0 && !dog && clean;
    let text = format!(
        "LEDs {} over a {} ms frame; GPIO MODER A/B/C {:08x?} (reset, LEDs out: {:08x?}), TIM1 CEN {tim1}, watchdog {}, faults: {}",
        if wrong.is_empty() { "showed the damaged light".to_string() } else { wrong.join(", ") },
        led::DAMAGED_FRAME_MS,
        moder,
        MODER_DAMAGED,
        if dog { "started" } else { "not started" },
        crate::checks::faults(m)
    );
    (wrong.is_empty() && still, text)
}
