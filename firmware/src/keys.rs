//! The push-buttons at the lathe: ENGAGE, STOP, PHASE+ and
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
//!   while it is held ENGAGE does nothing (a console `engage` meanwhile is
//!   stopped again within `STOP_EVERY_MS`);
//! * a key already down at power-up (held, or shorted) does nothing until
//!   it has been released: a reset mid-job never engages by itself;
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
    /// released at least once since power-up: only then does it act
    armed: bool,
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
    /// a key down at the first sample counts only once released
    seeded: bool,
}

impl Keys {
    /// Takes the raw levels (true = pressed, index = `Key as usize`) at
    /// `now_ms`, and says what to do.
    pub fn sample(&mut self, now_ms: u32, pressed: [bool; 4]) -> Events {
        if !self.seeded {
            self.seeded = true;
            for (k, &p) in self.keys.iter_mut().zip(&pressed) {
                // down already: its press happened before we looked
                *k = Debounced { pressed: p, raw: p, raw_since: now_ms, pressed_at: now_ms, next_repeat: 0, armed: !p };
            }
        }
        let mut edge = [false; 4];
        for (i, k) in self.keys.iter_mut().enumerate() {
            edge[i] = k.sample(now_ms, pressed[i]) && k.armed;
            k.armed |= !k.pressed;
        }
        let [_, stop, plus, minus] = &mut self.keys;
        // (a STOP down since power-up still holds ENGAGE off)
        let stop_held = stop.pressed;
        let stop_again = stop.repeat(now_ms, STOP_EVERY_MS, STOP_EVERY_MS) && stop.armed;
        let up = edge[Key::PhasePlus as usize] || plus.repeat(now_ms, REPEAT_AFTER_MS, REPEAT_EVERY_MS) && plus.armed;
        let down =
            edge[Key::PhaseMinus as usize] || minus.repeat(now_ms, REPEAT_AFTER_MS, REPEAT_EVERY_MS) && minus.armed;
        let both = plus.pressed && minus.pressed;
        Events {
            stop: edge[Key::Stop as usize] || stop_again,
            engage: edge[Key::Engage as usize] && !stop_held,
            phase: if both || stop_held { 0 } else { up as i8 - down as i8 },
        }
    }
}

/// The phase after a nudge of `dir` (+1/−1), or None past ±360 degrees
/// (the press is refused). Not wrapped: the phase offset is linear in
/// degrees, so 359.5 → 0.5 would swing the cutter a whole turn back while
/// it cuts.
pub fn nudged_phase(mdeg: i32, dir: i8) -> Option<i32> {
    let next = mdeg + dir as i32 * PHASE_STEP_MDEG;
    (next.abs() <= 360_000).then_some(next)
}

#[cfg(test)]
mod tests;
