use super::*;

/// A NOR flash that loses power after `budget` byte operations: the byte
/// being erased or programmed is left half done (some bits), the rest as
/// they were. Programming can only clear bits, as on real flash.
struct MockFlash {
    slots: Vec<Vec<u8>>,
    budget: Option<usize>,
    noise: u8,
    /// writes report success but program nothing (a worn or protected
    /// sector)
    deaf: bool,
}

#[derive(Debug, PartialEq)]
struct PowerCut;

impl MockFlash {
    fn new() -> MockFlash {
        MockFlash { slots: vec![vec![0xFF; SLOT_LEN]; 2], budget: None, noise: 0x5A, deaf: false }
    }
    fn spend(&mut self) -> Result<(), PowerCut> {
        match &mut self.budget {
            Some(0) => Err(PowerCut),
            Some(n) => {
                *n -= 1;
                Ok(())
            }
            None => Ok(()),
        }
    }
}

impl SlotFlash for MockFlash {
    type Error = PowerCut;
    fn erase(&mut self, slot: usize) -> Result<(), PowerCut> {
        for i in 0..SLOT_LEN {
            if self.spend().is_err() {
                self.slots[slot][i] |= self.noise; // half-erased byte
                return Err(PowerCut);
            }
            self.slots[slot][i] = 0xFF;
        }
        Ok(())
    }
    fn write(&mut self, slot: usize, offset: u32, data: &[u8]) -> Result<(), PowerCut> {
        assert_eq!(offset % 4, 0, "aligned writes only");
        for (i, &b) in data.iter().enumerate() {
            let at = offset as usize + i;
            if self.spend().is_err() {
                self.slots[slot][at] &= b | self.noise; // some bits programmed
                return Err(PowerCut);
            }
            if !self.deaf {
                self.slots[slot][at] &= b;
            }
        }
        Ok(())
    }
    fn read(&mut self, slot: usize, offset: u32, buf: &mut [u8]) -> Result<(), PowerCut> {
        let o = offset as usize;
        buf.copy_from_slice(&self.slots[slot][o..o + buf.len()]);
        Ok(())
    }
}

const HEADER: CamHeader =
    CamHeader { points: 4, period_counts: 900, counts_per_rev: 2400, max_rate_hz: 12_000, max_accel: 1_600_000 };
const CAM_OLD: [i32; 4] = [7, -3, 200, 5];
const CAM_NEW: [i32; 4] = [9, 8, -7, 6];

#[test]
fn a_saved_cam_table_loads_back_and_a_corrupt_one_is_refused() {
    let mut f = MockFlash::new();
    save(&mut f, &settings("3"), Some((HEADER, &CAM_NEW[..]))).unwrap();
    let (_, Loaded::Saved { slot, .. }) = load(&mut f) else { panic!("saved") };
    assert_eq!(load_cam(&mut f, slot), Some(HEADER));
    f.slots[slot][CAM_POINTS_AT as usize + 5] ^= 0x10; // one bit of one point
    assert_eq!(load_cam(&mut f, slot), None);
    save(&mut f, &settings("3"), None).unwrap();
    assert_eq!(load_cam(&mut f, 1 - slot), None, "saved without a cam");
}

fn settings(ratio: &str) -> Config {
    Config::default().with("max-rpm", "500").unwrap().with("ratio", ratio).unwrap()
}

#[test]
fn empty_or_corrupt_flash_loads_the_defaults_and_says_so() {
    let mut f = MockFlash::new();
    assert_eq!(load(&mut f), (Config::default(), Loaded::Defaults));
    f.slots = vec![vec![0x37; SLOT_LEN]; 2];
    assert_eq!(load(&mut f), (Config::default(), Loaded::Defaults));
}

#[test]
fn the_newest_save_wins_across_many_saves() {
    let mut f = MockFlash::new();
    for (i, r) in ["3", "5/2", "11/3", "4/3", "2"].iter().enumerate() {
        assert_eq!(save(&mut f, &settings(r), None), Ok(i as u32 + 1));
        assert_eq!(load(&mut f).0, settings(r));
    }
}

#[test]
fn a_power_cut_at_every_point_leaves_the_old_or_the_new_never_a_mix() {
    let (old, new) = (settings("11/3"), settings("5/2"));
    for history in 0..3 {
        let mut cut_points = 0;
        for budget in 0.. {
            let mut f = MockFlash::new();
            for _ in 0..history {
                save(&mut f, &settings("3"), None).unwrap();
            }
            save(&mut f, &old, Some((HEADER, &CAM_OLD[..]))).unwrap();
            f.budget = Some(budget);
            let finished = save(&mut f, &new, Some((HEADER, &CAM_NEW[..]))).is_ok();
            f.budget = None;
            let (got, how) = load(&mut f);
            assert!(matches!(how, Loaded::Saved { .. }));
            assert!(got == old || got == new, "history {history}, cut after {budget} ops: a mix");
            // the cam table saved with those settings comes back with them
            let Loaded::Saved { slot, .. } = how else { unreachable!() };
            assert_eq!(load_cam(&mut f, slot), Some(HEADER), "history {history}, cut after {budget}");
            let first = f.slots[slot][CAM_POINTS_AT as usize];
            assert_eq!(first, if got == old { 7 } else { 9 }, "the table saved with those settings");
            if finished {
                assert_eq!(got, new);
                break;
            }
            cut_points += 1;
        }
        assert!(cut_points >= SLOT_LEN + RECORD, "every erase and write byte was a cut point");
    }
}

#[test]
fn a_save_the_flash_took_but_did_not_keep_is_an_error_and_the_old_settings_stay() {
    let mut f = MockFlash::new();
    save(&mut f, &settings("3"), None).unwrap();
    f.deaf = true;
    assert_eq!(save(&mut f, &settings("5"), None), Err(SaveError::Verify));
    assert_eq!(load(&mut f).0, settings("3"));
}

#[test]
fn a_cam_that_does_not_read_back_fails_the_save() {
    let mut f = MockFlash::new();
    save(&mut f, &settings("3"), None).unwrap();
    // the settings record lands, the cam's points do not
    struct CamDeaf(MockFlash);
    impl SlotFlash for CamDeaf {
        type Error = PowerCut;
        fn erase(&mut self, slot: usize) -> Result<(), PowerCut> {
            self.0.erase(slot)
        }
        fn write(&mut self, slot: usize, offset: u32, data: &[u8]) -> Result<(), PowerCut> {
            if offset >= CAM_POINTS_AT {
                return Ok(());
            }
            self.0.write(slot, offset, data)
        }
        fn read(&mut self, slot: usize, offset: u32, buf: &mut [u8]) -> Result<(), PowerCut> {
            self.0.read(slot, offset, buf)
        }
    }
    let mut d = CamDeaf(f);
    assert_eq!(save(&mut d, &settings("5"), Some((HEADER, &CAM_NEW[..]))), Err(SaveError::Verify));
}

#[test]
fn a_slot_saved_before_the_extension_block_loads_with_its_defaults() {
    // what the previous firmware wrote: the record and the marker, the
    // extension's place left erased
    let mut f = MockFlash::new();
    let old = settings("11/3");
    f.write(0, 0, &body(&old, 7)).unwrap();
    f.write(0, BODY as u32, &MARKER).unwrap();
    assert_eq!(load(&mut f), (old, Loaded::Saved { seq: 7, slot: 0 }));
    // and a save now keeps the new settings beside it
    let new = old.with("cutter-cpr", "1000").unwrap().with("lost-steps", "40").unwrap();
    assert_eq!(save(&mut f, &new, None), Ok(8));
    assert_eq!(load(&mut f).0, new);
}

#[test]
fn a_damaged_extension_block_refuses_its_slot() {
    let mut f = MockFlash::new();
    let a = settings("3").with("cutter-cpr", "4000").unwrap();
    let b = settings("5/2").with("cutter-cpr", "1000").unwrap();
    assert_eq!(save(&mut f, &a, None), Ok(1));
    assert_eq!(save(&mut f, &b, None), Ok(2));
    f.slots[1][EXT_AT as usize + 5] ^= 0x10; // the newer slot's cutter-cpr
    assert_eq!(load(&mut f).0, a, "the older intact slot, not b with a wrong encoder");
}
