//! nanoELS H5 (kachurovskiy/nanoels at d55f9ee, `h5/h5.ino`): its main
//! loop polls the spindle's pulse counter, follows it through a 3-count
//! backlash filter (`spindlePosAvg`, L9580-9634), sets the target to
//! trunc(f32 chain of count · steps per count) (`posFromSpindle`,
//! L7234-7247) and steps toward it (`moveAxis`, L8987-9033): one step per
//! pass at most, once 1e6/speed − 5 µs have passed since the last; after
//! each step speed ← trunc(speed + accel/speed); a reversal restarts at
//! the start speed after a 10 µs DIR delay; idle passes lower the speed
//! by 1 step/s.
//!
//! Choices for the comparison (the firmware does not fix them): the loop
//! runs every `LOOP_S`; the counter is given the same ×4 count as the
//! others (nanoELS decodes ×2: this flatters it); start speed and
//! acceleration are this motor's (`max-accel`), not nanoELS's defaults
//! (800 steps/s and 20 000 steps/s², whose plateau at 20 001 steps/s is
//! below every scenario's cutter speed).

/// The main loop's period, s: not stated by the firmware (a guess).
pub const LOOP_S: f64 = 10e-6;
/// `ENCODER_BACKLASH`, counts.
const BACKLASH: i64 = 3;
/// `DIRECTION_SETUP_DELAY_US` (H5), s.
const DIR_DELAY_S: f64 = 10e-6;

pub struct NanoEls {
    /// the chain's terms: motor steps, the pitch's denominator, encoder
    /// counts, the pitch's numerator with the sense (`posFromSpindle`)
    chain: [f32; 4],
    speed_start: i64,
    accel: i64,
    speed: i64,
    pos: i64,
    avg: i64,
    forward: bool,
    /// the last step's time, µs (`micros()`)
    step_start_us: i64,
}

impl NanoEls {
    /// Steps per count as nanoELS's chain computes them: `motor_steps` ·
    /// `num` / (`den` · `counts`), `num` signed by the sense (its screw
    /// pitch is our ratio's denominator, its thread pitch the numerator);
    /// start speed steps/s, accel steps/s².
    pub fn new((motor_steps, num, den, counts): (u32, i64, u64, u32), speed_start: i64, accel: i64) -> NanoEls {
        NanoEls {
            chain: [motor_steps as f32, den as f32, counts as f32, num as f32],
            speed_start,
            accel,
            speed: speed_start,
            pos: 0,
            avg: 0,
            forward: true,
            step_start_us: i64::MIN / 2,
        }
    }

    /// One pass of the loop at `t` (s) with the counter's `count`: the
    /// step it makes and when (s), if any.
    pub fn pass(&mut self, t: f64, count: i64) -> Option<(f64, i32)> {
        if count > self.avg {
            self.avg = count;
        } else if count < self.avg - BACKLASH {
            self.avg = count + BACKLASH;
        }
        // `s * motorSteps / screwPitch / ENCODER_STEPS_FLOAT * pitch`, in
        // f32 from left to right, truncated
        let [m, den, e, num] = self.chain;
        let target = (self.avg as f32 * m / den / e * num) as i64;
        let pending = target - self.pos;
        if pending == 0 {
            self.speed = (self.speed - 1).max(self.speed_start);
            return None;
        }
        let now_us = (t * 1e6).round() as i64; // (`micros()`: the passes fall on whole µs)
        let delay_us = 1e6 / self.speed as f64;
        if ((now_us - self.step_start_us) as f64) < delay_us - 5.0 {
            return None;
        }
        let forward = pending > 0;
        let mut at = t;
        if forward != self.forward {
            (self.forward, self.speed) = (forward, self.speed_start);
            at += DIR_DELAY_S;
        }
        let d = if forward { 1 } else { -1 };
        self.pos += d as i64;
        // (f32 in the firmware: `acceleration * delayUs / 1000000.0`)
        let gain = (self.accel as f64 * delay_us / 1e6) as i64;
        self.speed = (self.speed + gain).max(self.speed_start);
        self.step_start_us = now_us;
        Some((at, d))
    }
}
