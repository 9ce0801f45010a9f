//! Quadrature counters: a 16-bit hardware counter extended to 64 bits, the
//! index pulse latched for absolute phase, and implausible jumps flagged.
//!
//! The hardware seam is `TickInput`: the tick reads the counter registers
//! into it, and the wrap-around logic lives here, property-tested on the host.

/// A 16-bit counter seen as a 64-bit position. Sampled every tick, so one
/// tick never moves half the range (the plausibility limit is far below it).
#[derive(Clone, Copy, Debug, Default)]
pub struct Extender {
    last: u16,
    position: i64,
}

impl Extender {
    pub fn new(raw: u16) -> Extender {
        Extender { last: raw, position: 0 }
    }

    /// Takes a new raw reading; returns the signed change since the last.
    #[inline]
    pub fn update(&mut self, raw: u16) -> i32 {
        let delta = raw.wrapping_sub(self.last) as i16 as i32;
        self.last = raw;
        self.position += delta as i64;
        delta
    }

    pub fn position(&self) -> i64 {
        self.position
    }

    /// The 64-bit position of a raw value captured since the last update
    /// (an index latch), within half the counter range of it.
    #[inline]
    pub fn position_of(&self, raw: u16) -> i64 {
        self.position + raw.wrapping_sub(self.last) as i16 as i64
    }
}

/// Index supervision: the first index sets the phase reference; later ones
/// must land a whole number of revolutions from it, give or take `slack`.
#[derive(Clone, Copy, Debug, Default)]
pub struct IndexTracker {
    reference: Option<i64>,
    last: Option<i64>,
}

/// What an index pulse told us.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IndexEvent {
    /// The first index: this count is now the phase reference.
    Referenced(i64),
    /// A later index, consistent with the reference.
    Consistent,
    /// A later index off by this many counts: counts were lost or gained.
    Slipped(i64),
}

impl IndexTracker {
    pub fn reference(&self) -> Option<i64> {
        self.reference
    }

    /// Checks an index latched at `position` against `counts_per_rev`.
    /// Uses only adds and compares: the offset from the last index is at
    /// most a few revolutions in any sane tick sequence.
    pub fn on_index(&mut self, position: i64, counts_per_rev: i64, slack: i64) -> IndexEvent {
        let Some(last) = self.last else {
            self.reference = Some(position);
            self.last = Some(position);
            return IndexEvent::Referenced(position);
        };
        self.last = Some(position);
        let mut off = position - last;
        // Reduce to (−E/2, E/2] by stepping; an index comes once per turn.
        let mut guard = 0;
        let half = counts_per_rev >> 1;
        while off > half && guard < 8 {
            off -= counts_per_rev;
            guard += 1;
        }
        while off <= -half && guard < 16 {
            off += counts_per_rev;
            guard += 1;
        }
        // Same index edge seen twice at reversal: 0 offset is consistent.
        if off.abs() <= slack {
            IndexEvent::Consistent
        } else {
            IndexEvent::Slipped(off)
        }
    }
}

#[cfg(test)]
mod pinned_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Reference model: a 64-bit walk; the hardware sees only its low 16 bits.
        #[test]
        fn extension_matches_a_64_bit_reference_through_every_wrap(
            start in any::<u16>(),
            steps in proptest::collection::vec(-32_767i32..=32_767, 1..500),
        ) {
            let mut truth = start as i64;
            let mut ext = Extender::new(start);
            for s in steps {
                truth += s as i64;
                let d = ext.update(truth as u16);
                prop_assert_eq!(d, s);
                prop_assert_eq!(ext.position(), truth - start as i64);
            }
        }

        #[test]
        fn a_latched_raw_value_maps_to_its_64_bit_position(base in -1_000_000_000i64..1_000_000_000, back in -30_000i64..30_000) {
            let mut ext = Extender::new(0);
            let mut pos = 0i64;
            let mut remaining = base;
            while remaining != 0 {
                let s = remaining.clamp(-30_000, 30_000);
                pos += s;
                remaining -= s;
                ext.update(pos as u16);
            }
            prop_assert_eq!(ext.position_of((pos + back) as u16), pos + back);
        }
    }

    #[test]
    fn index_slip_is_reported_with_its_size() {
        let mut t = IndexTracker::default();
        assert_eq!(t.on_index(100, 2400, 2), IndexEvent::Referenced(100));
        assert_eq!(t.on_index(2501, 2400, 2), IndexEvent::Consistent);
        assert_eq!(t.on_index(2501 + 2400 - 9, 2400, 2), IndexEvent::Slipped(-9));
        assert_eq!(t.on_index(2501 + 2400 - 9 - 2400, 2400, 2), IndexEvent::Consistent);
    }
}
