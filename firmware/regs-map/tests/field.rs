//! `Field`'s arithmetic: a value in place, read back, and refused when it is
//! wider than its field.
use polyturn_regs::bits::{dma_cr, Field};

#[test]
fn a_value_wider_than_its_field_is_refused() {
    assert_eq!(dma_cr::CHSEL.val(7), 7 << 25);
    assert!(std::panic::catch_unwind(|| dma_cr::CHSEL.val(8)).is_err());
}

#[test]
fn a_field_reads_back_what_it_placed() {
    let f = Field::new(4, 3);
    assert_eq!(f.mask(), 0x70);
    assert_eq!(f.get(f.val(5) | 0x8F), 5);
    assert!(Field::bit(31).on(1 << 31) && !Field::bit(31).on(!(1 << 31)));
    assert_eq!(Field::new(0, 32).mask(), u32::MAX);
}
