//! Interrupt numbers and peripheral base addresses of the STM32F411CE, from ST's
//! SVD as stm32-metapac carries it: nothing about them is typed in here.

use stm32_metapac::metadata::METADATA;

pub fn irq(name: &str) -> usize {
    METADATA
        .interrupts
        .iter()
        .find(|i| i.name == name)
        .unwrap_or_else(|| panic!("no interrupt {name} in the SVD"))
        .number as usize
}

pub fn base(name: &str) -> u32 {
    METADATA
        .peripherals
        .iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("no peripheral {name} in the SVD"))
        .address as u32
}

/// The interrupts whose handler the image defines under the SVD's name but whose
/// vector points elsewhere: ties the SVD's numbers to this image.
pub fn misplaced_handlers(image: &crate::image::Image) -> Vec<String> {
    METADATA
        .interrupts
        .iter()
        .filter(|i| {
            let v = image.vectors.get(16 + i.number as usize);
            matches!((image.symbols.get(i.name), v), (Some(&a), Some(&v)) if v & !1 != a)
        })
        .map(|i| i.name.to_string())
        .collect()
}
