//! Commands and status: called at low priority (console, USB, planning).
//! Anything needing a division happens here, never in the tick.

use super::{Controller, Refusal};
use crate::config::Config;
use crate::derived::Derived;
use crate::follower::Follower;
use crate::gear::Gear;
use crate::state::{Fault, State};
use crate::timing::Timing;

/// A snapshot for `status`, `watch` and the once-a-second log.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    pub state: State,
    /// the lathe's speed, Q32 counts per tick: positive while its encoder
    /// counts up, whatever `dir` (the estimator's own sign follows `dir`)
    pub lathe_velocity_q32: i64,
    /// target − commanded cutter position, Q16 steps
    pub phase_error_q16: i64,
    /// the cutter's commanded speed, Q16 steps per tick in the motor's own
    /// sense: 0 while idle, the gear's speed once synced
    pub cutter_velocity_q16: i64,
    /// the cutter's position (steps emitted, or its encoder)
    pub cutter_steps: i64,
    /// the exact rounded gear target, whole steps
    pub target_steps: i64,
    pub lathe_counts: i64,
    pub indexed: bool,
    /// the count latched at the first index seen: the spindle's angle is
    /// from it (`crate::angle`), else from the count at the start
    pub index_counts: Option<i64>,
    /// while dividing (`divide N`), the divisions of a turn
    pub divisions: Option<u32>,
    pub ticks: u64,
}

impl Controller {
    pub fn state(&self) -> State {
        self.state
    }
    pub fn config(&self) -> &Config {
        &self.config
    }
    /// Changes with every change of the settings (`install_config`).
    pub fn config_generation(&self) -> u32 {
        self.config_generation
    }

    pub fn timing(&self) -> Timing {
        self.timing
    }

    pub fn derived(&self) -> &Derived {
        &self.d
    }
    pub fn follower(&self) -> &Follower {
        &self.follower
    }

    pub fn status(&self) -> Status {
        Status {
            state: self.state,
            lathe_velocity_q32: if self.d.sense_positive { self.est.velocity_q32() } else { -self.est.velocity_q32() },
            phase_error_q16: self.target
                - self.follower.position
                - (self.target_velocity - self.follower.velocity) * self.ahead(),
            cutter_velocity_q16: self.follower.velocity,
            cutter_steps: self.cutter_steps(),
            target_steps: self.gear.steps(),
            lathe_counts: self.lathe.position(),
            indexed: self.index.reference().is_some(),
            index_counts: self.index.reference(),
            divisions: self.dividing(),
            ticks: self.ticks,
        }
    }

    fn cutter_steps(&self) -> i64 {
        match self.config.drive {
            crate::config::DriveKind::Stepper => self.steps.position(),
            crate::config::DriveKind::Bldc | crate::config::DriveKind::None => self.follower.position >> 16,
        }
    }

    /// Starts synchronising (from rest or while the lathe turns). Never
    /// inlined, as `disengage` and `rebase`: the emulator finds each command's
    /// entry by its symbol (emu/src/tape.rs).
    #[inline(never)]
    pub fn engage(&mut self) -> Result<(), Refusal> {
        self.admit(super::activity::Asked::Engage)?;
        // with no cutter and no X axis, engaging would move nothing yet
        // report `synced` and assert ENABLE
        if self.config.drive == crate::config::DriveKind::None && self.x.is_none() {
            return Err(Refusal::NothingToDrive);
        }
        let margin = self.d.limits.max_velocity - self.d.limits.max_velocity / 16;
        if self.target_velocity.abs() > margin {
            return Err(Refusal::Overspeed);
        }
        self.service();
        self.drop_whole_turns();
        self.ever_engaged = true;
        self.state = State::Engaging;
        info!("engaging");
        Ok(())
    }

    /// Ramps the cutter down and goes idle.
    #[inline(never)]
    pub fn disengage(&mut self) {
        if matches!(self.state, State::Engaging | State::Synced | State::Jogging) {
            self.end_jog();
            self.state = State::Disengaging;
            info!("disengaging");
        }
    }

    /// Clears a latched fault once the motor has stopped. The gear is
    /// re-based on the lathe's position: after an implausible jump the
    /// clamped gear no longer matched the counter.
    pub fn clear(&mut self) {
        if let State::Fault(_) = self.state {
            self.state = if self.follower.velocity == 0 { State::Idle } else { State::Disengaging };
            self.rebase();
        }
    }

    /// Low-priority housekeeping: re-bases the gear on the first index
    /// (only before the first engagement, so later passes keep the phase of
    /// the first).
    pub fn service(&mut self) {
        self.sample_check();
        if self.rebase_pending && self.state == State::Idle {
            self.rebase_pending = false;
            self.origin = self.index.reference().unwrap_or(self.origin);
            self.rebase();
        }
    }

    /// Whole cutter turns are equivalent (one turn rotates the section by
    /// 2π/GR, and N/GR = Z·q/gcd(pZ, q) is whole), so engaging catches up
    /// at most half a turn instead of every turn missed since boot. Exact:
    /// the offset is a whole number of M steps.
    fn drop_whole_turns(&mut self) {
        let m = self.config.motor_steps_per_rev as i64;
        let behind = (self.target - self.follower.position) >> 16;
        let turns = (behind + behind.signum() * m / 2) / m;
        self.turns -= turns * m;
        self.target -= (turns * m) << 16;
    }

    /// Whole-turn offset (steps) applied to the gear target.
    pub fn turn_offset_steps(&self) -> i64 {
        self.turns
    }

    /// The lathe count the gear measures from (0 at boot, or the first
    /// index if it came before the first engagement).
    pub fn gear_origin(&self) -> i64 {
        self.origin
    }

    /// Fits an X axis driven by `cam` (or removes it); only while idle.
    pub fn set_x_axis(&mut self, x: Option<super::XAxis>) -> Result<(), Refusal> {
        if self.state != State::Idle {
            return Err(Refusal::NotIdle);
        }
        self.x = x;
        self.rebase();
        Ok(())
    }

    /// Fits the X axis to an uploaded (or stored) cam table; only while
    /// idle, for this encoder, and no faster than one X step per two ticks
    /// (the firmware's X step output).
    pub fn fit_cam(&mut self, h: &crate::cam_upload::CamHeader, table: &'static [i32]) -> Result<(), &'static str> {
        let x = prepare_cam(h, table, self.timing)?;
        self.install_cam(h, x)
    }

    /// The quick half of `fit_cam`, for a cam `prepare_cam` built: the
    /// firmware calls it under the tick's lock, the long half outside.
    pub fn install_cam(&mut self, h: &crate::cam_upload::CamHeader, x: super::XAxis) -> Result<(), &'static str> {
        self.check_cam(h)?;
        self.set_x_axis(Some(x)).map_err(|r| r.describe())
    }

    /// Whether a cam with this header would fit (before it is stored).
    pub fn check_cam(&self, h: &crate::cam_upload::CamHeader) -> Result<(), &'static str> {
        if self.state != State::Idle {
            return Err("stop first: the cam changes only while idle");
        }
        if h.counts_per_rev != self.config.encoder_counts_per_rev {
            return Err("cam table made for another cpr: set cpr or remake the table");
        }
        crate::cam_upload::check_axis(h, self.timing.tick_hz)
    }

    pub fn x_axis(&self) -> Option<&super::XAxis> {
        self.x.as_ref()
    }

    #[inline(never)]
    pub(super) fn rebase(&mut self) {
        let rel = self.lathe.position() - self.origin;
        if let Some(x) = &mut self.x {
            x.cam.seek(rel);
            x.last_target = x.cam.position_q16(0);
        }
        self.gear = Gear::new(self.d.scale);
        self.gear.reset(if self.d.sense_positive { rel } else { -rel });
    }

    /// Whether settings may change now: while the cutter runs (or still
    /// ramps down from a fault) only the phase offset may. Asked first, so
    /// that a setting refused for being engaged is told "stop first", not
    /// how it fits with the others.
    #[inline]
    pub fn settings_may_change(&self, only_phase: bool) -> Result<(), Refusal> {
        let running = !matches!(self.state, State::Idle | State::Fault(_));
        let stopping = matches!(self.state, State::Fault(f) if !f.immediate()) && self.follower.velocity != 0;
        match (running && !only_phase) || stopping {
            true => Err(Refusal::NotIdle),
            false => Ok(()),
        }
    }

    /// Replaces the settings. While running only the phase offset may
    /// change (a nudge, smoothed by the follower's limits).
    pub fn set_config(&mut self, c: Config) -> Result<(), Refusal> {
        self.install_config(&PreparedConfig::prepare(c, &self.config, self.timing))
    }

    /// `set_config` with its figures derived beforehand, outside the tick's
    /// lock (`Derived::new` costs about 1 400 instructions; the swap here is
    /// short). `p` was prepared from the settings in force: the caller
    /// checks `config_generation` is the one it prepared from. By
    /// reference: only what changes is copied (the settings, and their
    /// figures while idle), under the tick's lock on the MCU.
    pub fn install_config(&mut self, p: &PreparedConfig) -> Result<(), Refusal> {
        let PreparedConfig { config: c, derived: d, only_phase, another_cutter } = p;
        let (only_phase, another_cutter) = (*only_phase, *another_cutter);
        self.settings_may_change(only_phase)?;
        if another_cutter && self.x.is_some() {
            return Err(Refusal::CamFitted);
        }
        let running = !matches!(self.state, State::Idle | State::Fault(_));
        if c.encoder_counts_per_rev != self.config.encoder_counts_per_rev && self.x.is_some() {
            // the cam's period is in counts of the old encoder
            warn!("cpr changed: the X cam table no longer fits, X axis off");
            self.x = None;
        }
        self.config = *c;
        self.config_generation = self.config_generation.wrapping_add(1);
        if running {
            // A phase nudge is a move the follower makes within its limits,
            // not lag: back to Engaging (no following-error check) until the
            // cutter is on the new phase, then Synced again. Checked as lag,
            // 10 degrees of a 3200-step cutter (89 steps) tripped the 64-step
            // limit on the next tick after `ok phase=10`.
            if d.phase_offset_q16 != self.d.phase_offset_q16 && self.state == State::Synced {
                self.state = State::Engaging;
            }
            self.d.phase_offset_q16 = d.phase_offset_q16;
            return Ok(());
        }
        self.d = *d;
        // The speed is measured afresh (its sign follows `dir`), but the
        // time since the encoder's last count is the encoder's, whatever
        // the settings: a lathe at rest stays at rest (`lathe_at_rest`).
        self.est = self.est.restarted(d.still_ticks);
        self.rebase();
        Ok(())
    }

    /// No lathe encoder count for the last 0.1 s (or since the start).
    pub fn lathe_at_rest(&self) -> bool {
        self.est.at_rest()
    }

    /// Ticks since the lathe encoder's last count (saturating). A board
    /// that has just started counts from the at-rest limit, and a flash
    /// stall that lost ticks from its end.
    pub fn ticks_since_lathe_count(&self) -> u32 {
        self.est.still_ticks()
    }

    pub fn fault(&self) -> Option<Fault> {
        match self.state {
            State::Fault(f) => Some(f),
            _ => None,
        }
    }
}

/// New settings with their figures derived (`Derived::new`, the long part),
/// outside the tick's lock, for `Controller::install_config`. Only
/// `prepare` builds one, so the figures are always those of the settings.
#[derive(Clone, Copy, Debug)]
pub struct PreparedConfig {
    config: Config,
    derived: Derived,
    /// whether `config` differs from the settings it was prepared from only
    /// in its phase (all that may change while running)
    only_phase: bool,
    /// whether `config` turns another cutter (`changes_the_cutter`):
    /// worked out here, outside the tick's lock
    another_cutter: bool,
}

impl PreparedConfig {
    /// `next` to replace `current` (a short copy of the settings in force),
    /// with the figures for `timing` (the controller's).
    pub fn prepare(next: Config, current: &Config, timing: Timing) -> PreparedConfig {
        PreparedConfig {
            config: next,
            derived: Derived::new(&next, timing),
            only_phase: next.differs_only_in_phase(current),
            another_cutter: changes_the_cutter(current, &next),
        }
    }

    pub fn config(&self) -> &Config {
        &self.config
    }

    pub fn derived(&self) -> &Derived {
        &self.derived
    }
}

/// The checks `prepare_cam` applies to the points, on a table not yet
/// stored (the firmware runs them on an upload before saving it, outside
/// the tick's lock: two passes over the points): the points themselves,
/// and what they ask of the X axis the header declares
/// (`cam_upload::motion`).
pub fn check_table(h: &crate::cam_upload::CamHeader, points: &[i32]) -> Result<(), crate::cam_upload::TableRefusal> {
    crate::cam::Cam::check(points, h.period_counts).map_err(|e| e.describe())?;
    crate::cam_upload::motion::check(h, points).map_err(crate::cam_upload::TableRefusal::Motion)
}

/// The long half of `Controller::fit_cam`, which needs no controller: the
/// table's points are checked (`Cam::new`, one pass over them) and the
/// limits derived. Runs outside the tick's lock: the check is about
/// 30 000 instructions, eight ticks, too long to hold the tick off.
pub fn prepare_cam(
    h: &crate::cam_upload::CamHeader,
    table: &'static [i32],
    timing: crate::timing::Timing,
) -> Result<super::XAxis, &'static str> {
    check_table(h, table).map_err(|e| e.describe())?;
    let cam = crate::cam::Cam::new(table, h.period_counts).map_err(|e| e.describe())?;
    let limits = crate::follower::Limits::from_rates(h.max_rate_hz as u64, h.max_accel as u64, timing.tick_hz as u64);
    Ok(super::XAxis::new(cam, limits))
}

/// Whether `next` turns another cutter than `now`: a cam table fitted for
/// one cutter (its period a whole number of the cutter's passes, made by
/// `polyturn compensate` for that ratio, those edges and that sense) would
/// run out of step with another. With no cutter before or after, ratio and edges move
/// nothing (a single-point tool's table takes any).
pub fn changes_the_cutter(now: &Config, next: &Config) -> bool {
    let none = |c: &Config| c.drive == crate::config::DriveKind::None;
    let turned = now.ratio != next.ratio || now.edges != next.edges || now.sense != next.sense;
    !(none(now) && none(next)) && (turned || now.drive != next.drive)
}
