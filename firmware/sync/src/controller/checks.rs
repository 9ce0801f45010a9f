//! The encoder check's hooks in the controller: the tick keeps the index
//! count and latch (`on_index`), `service` samples them at low priority.

use super::activity::{Activity, Asked};
use super::{Controller, Refusal};
use crate::check::{EncoderCheck, EncoderReport, Sample};

/// The check's hands-off window: the first second.
pub const STILL_SECONDS: u64 = 1;

impl Controller {
    fn check_sample(&self) -> Sample {
        Sample {
            ticks: self.ticks,
            counts: self.lathe.position(),
            indexes: self.index_seen,
            last_index: self.last_index,
        }
    }

    /// Starts (or restarts) the encoder check, only while idle: its reply
    /// has the machinist turn the chuck by hand, which is never safe with
    /// the cutter engaged, jogging or in a self-test (whose generator, not
    /// the encoder, drives the count), nor with a fault latched.
    pub fn start_encoder_check(&mut self) -> Result<(), Refusal> {
        self.admit(Asked::Check)?;
        let still = STILL_SECONDS * self.timing.tick_hz as u64;
        let check = EncoderCheck::new(self.check_sample(), still, self.d.max_counts_per_tick as i64);
        self.activity = Activity::Check(check);
        Ok(())
    }

    /// True while an encoder check runs (`engage` waits for its end).
    pub fn encoder_check_running(&self) -> bool {
        matches!(self.activity, Activity::Check(_))
    }

    /// The figures so far, if a check runs.
    pub fn encoder_check(&self) -> Option<EncoderReport> {
        match &self.activity {
            Activity::Check(c) => Some(c.report()),
            _ => None,
        }
    }

    /// Ends the check, with its last figures.
    pub fn stop_encoder_check(&mut self) -> Option<EncoderReport> {
        let report = self.encoder_check()?;
        self.activity = Activity::None;
        Some(report)
    }

    /// Feeds the check (from `service`).
    pub(super) fn sample_check(&mut self) {
        let s = self.check_sample();
        if let Activity::Check(c) = &mut self.activity {
            c.sample(s);
        }
    }
}
