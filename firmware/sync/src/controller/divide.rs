//! `divide N`: the spindle turned by hand to N equal divisions of a turn,
//! with the cutter off (a jog aside). The controller only keeps the
//! number; `status` works the spindle's place out at low priority
//! (`crate::angle`) from the count and the index's, which the tick keeps.

use super::activity::{Activity, Asked, Divide};
use super::{Controller, Refusal};
use crate::config::table::DIVIDE;

impl Controller {
    /// Starts dividing a turn into `divisions` (or changes their number):
    /// within `DIVIDE`'s range and at most one per four counts of the
    /// encoder, so the tolerance of each (± one count, `angle`) never
    /// reaches the next.
    pub fn start_divide(&mut self, divisions: u32) -> Result<(), Refusal> {
        self.admit(Asked::Divide)?;
        if !DIVIDE.contains(divisions) || divisions > self.config.encoder_counts_per_rev / 4 {
            return Err(Refusal::DivideRange);
        }
        self.activity = Activity::Divide(Divide { divisions });
        Ok(())
    }

    /// Ends dividing (also under a jog asked for while dividing, which
    /// then ends as a plain jog); the number of divisions it had.
    pub fn stop_divide(&mut self) -> Option<u32> {
        let was = self.divide()?;
        match &mut self.activity {
            Activity::Jog(j) => j.dividing = None,
            _ => self.activity = Activity::None,
        }
        Some(was.divisions)
    }

    /// The divisions of a turn while dividing.
    pub fn dividing(&self) -> Option<u32> {
        self.divide().map(|d| d.divisions)
    }

    pub(super) fn divide(&self) -> Option<Divide> {
        match self.activity {
            Activity::Divide(d) => Some(d),
            Activity::Jog(j) => j.dividing,
            _ => None,
        }
    }
}
