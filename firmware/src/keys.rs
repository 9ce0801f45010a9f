//! The push-buttons at the lathe (issue 14): ENGAGE, STOP, PHASE+ and
//! PHASE−, each a switch to GND on a pin with its pull-up (pressed = low,
//! `board::PINS`). Sampled every millisecond at low priority (the planning
//! executor, `app/keys.rs`), never by an interrupt: a chattering key costs
//! the control tick nothing.
//!
//! What a machinist expects of them, and what the tests pin:
//! * a key counts once it has held its new level for `DEBOUNCE_MS`; a key
//!   that chatters faster never counts;
//! * ENGAGE acts once per press, however long it is held;
//! * STOP acts on its press and again every `STOP_EVERY_MS` while held, and
//!   while it is held ENGAGE does nothing (a held STOP keeps the cutter
//!   stopped, whatever the console asks);
//! * PHASE+ and PHASE− nudge once per press, then repeat after
//!   `REPEAT_AFTER_MS` every `REPEAT_EVERY_MS` while held (each nudge is a
//!   phase change the follower makes within its limits); both at once do
//!   nothing.

pub const DEBOUNCE_MS: u32 = 20;
pub const STOP_EVERY_MS: u32 = 250;
pub const REPEAT_AFTER_MS: u32 = 500;
pub const REPEAT_EVERY_MS: u32 = 250;
/// One PHASE press turns the cutter's phase by 1 degree (the flats turn by
/// 1/GR degree of the work).
pub const PHASE_STEP_MDEG: i32 = 1_000;

/// The keys, in the order `Keys::sample` takes their levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Engage = 0,
    Stop = 1,
    PhasePlus = 2,
    PhaseMinus = 3,
}

/// What one sample asks of the controller.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Events {
    pub stop: bool,
    pub engage: bool,
    /// phase nudges: +1, −1 or 0
    pub phase: i8,
}

#[derive(Clone, Copy, Debug, Default)]
struct Debounced {
    /// the debounced level (true = pressed)
    pressed: bool,
    /// the raw level last seen, and since when
    raw: bool,
    raw_since: u32,
    /// when the debounced press began, and the next repeat is due
    pressed_at: u32,
    next_repeat: u32,
}

impl Debounced {
    /// Takes a raw level; true if the debounced level just became pressed.
    fn sample(&mut self, now: u32, raw: bool) -> bool {
        if raw != self.raw {
            self.raw = raw;
            self.raw_since = now;
        }
        let settled = now.wrapping_sub(self.raw_since) >= DEBOUNCE_MS;
        if settled && self.raw != self.pressed {
            self.pressed = self.raw;
            self.pressed_at = now;
            return self.pressed;
        }
        false
    }

    /// While held: true every `every` ms after `first` ms.
    fn repeat(&mut self, now: u32, first: u32, every: u32) -> bool {
        let held = now.wrapping_sub(self.pressed_at);
        if !self.pressed || held < first {
            self.next_repeat = first;
            return false;
        }
        if held >= self.next_repeat {
            self.next_repeat = held + every;
            return true;
        }
        false
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub struct Keys {
    keys: [Debounced; 4],
}

impl Keys {
    /// Takes the raw levels (true = pressed, index = `Key as usize`) at
    /// `now_ms`, and says what to do.
    pub fn sample(&mut self, now_ms: u32, pressed: [bool; 4]) -> Events {
        let mut edge = [false; 4];
        for (i, k) in self.keys.iter_mut().enumerate() {
            edge[i] = k.sample(now_ms, pressed[i]);
        }
        let [_, stop, plus, minus] = &mut self.keys;
        let stop_held = stop.pressed;
        let stop_again = stop.repeat(now_ms, STOP_EVERY_MS, STOP_EVERY_MS);
        let up = edge[Key::PhasePlus as usize] || plus.repeat(now_ms, REPEAT_AFTER_MS, REPEAT_EVERY_MS);
        let down = edge[Key::PhaseMinus as usize] || minus.repeat(now_ms, REPEAT_AFTER_MS, REPEAT_EVERY_MS);
        let both = plus.pressed && minus.pressed;
        Events {
            stop: edge[Key::Stop as usize] || stop_again,
            engage: edge[Key::Engage as usize] && !stop_held,
            phase: if both || stop_held { 0 } else { up as i8 - down as i8 },
        }
    }
}

/// The phase after a nudge of `dir` (+1/−1), kept within ±360 degrees:
/// a whole cutter turn later is the same phase.
pub fn nudged_phase(mdeg: i32, dir: i8) -> i32 {
    let next = mdeg + dir as i32 * PHASE_STEP_MDEG;
    if next > 360_000 {
        next - 360_000
    } else if next < -360_000 {
        next + 360_000
    } else {
        next
    }
}

#[cfg(test)]
mod tests;
