//! When a section is a polygon and when it is round to the eye and the
//! finger: one rule for `geometry`, `simulate`, `compensate` and the
//! setups `setups` lists, so that no command lists what another refuses.

use super::{Section, SectionSummary, Setup};

/// A section is nearly round when its roundness fraction is above this.
pub const ROUND_FRACTION: f64 = 0.5;

/// How round a section is, and the words that say so.
#[derive(Clone, Debug)]
pub struct Roundness {
    /// 0 a clean polygon, 1 a circle
    pub fraction: f64,
    pub says: String,
}

impl Roundness {
    pub fn is_round(&self) -> bool {
        self.fraction > ROUND_FRACTION
    }

    /// The exact model's section of `setup`, judged (what `geometry` draws):
    /// each bin solved on the pass, one sector tiled round
    /// (`Section::ideal_tiled`). A polyline through the pass (`ideal`) is
    /// as good on a real section but not on one a few µm across, and costs
    /// `setups`, which judges every row, many times more.
    pub fn of_setup(setup: &Setup) -> (Roundness, Section) {
        let (round, section, _) = Roundness::of_setup_summed(setup);
        (round, section)
    }

    /// [`Roundness::of_setup`] with the section's summary it judged by.
    pub fn of_setup_summed(setup: &Setup) -> (Roundness, Section, SectionSummary) {
        let section = Section::ideal_tiled(setup, Section::default_bins(setup.sides()));
        let summary = section.summary();
        (Roundness::of(&summary, setup.depth_mm), section, summary)
    }

    /// From three sides up, a circle has N "flats" too, each bulging
    /// R(1 - cos(pi/N)) from its chord: a section whose flats bulge more
    /// than half that is round (else a 0.002 mm cutter's shaved circle
    /// would come out as 6 sharp sides). One or two "flats" of a circle
    /// are no chord to bulge from (1 - cos(pi/N) is 2 or 1: a flat through
    /// the centre), so there a flat must stand out from the round, corner
    /// to flat, by more than half the depth of cut (a cutter that barely
    /// turns shaves a circle, all of it at the depth).
    pub fn of(s: &SectionSummary, depth_mm: f64) -> Roundness {
        if s.sides >= 3 {
            let circle = s.circumscribed_radius * (1.0 - (std::f64::consts::PI / s.sides as f64).cos());
            let fraction = s.flat_deviation.abs() / circle;
            return Roundness {
                fraction,
                says: format!("its flats bulge {:.0} % as much as a circle's", fraction * 100.0),
            };
        }
        let relief = s.circumscribed_radius - s.inscribed_radius;
        let fraction = (1.0 - relief / depth_mm).clamp(0.0, 1.0);
        let says = format!("its flats stand {relief:.4} mm below its corners, under half the {depth_mm} mm depth");
        Roundness { fraction, says }
    }
}
