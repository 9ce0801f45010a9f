//! The setup's arithmetic, apart from any port or prompt: the
//! encoder check's reply, the proposals made from it, the motor's steps
//! per cutter turn, the sense setting, and the fastest lathe speed each
//! ratio allows. Everything exact (integers and reduced fractions).

use polyturn_sync::config::table::{CPR, STEPS};
use polyturn_sync::{Config, Sense};
use std::collections::BTreeMap;

/// The figures of an `ok encoder ...` reply (`console/checks.rs`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EncoderFigures {
    pub moved: i64,
    pub backward: u64,
    pub jumps: u64,
    pub chatter: u64,
    pub indexes: u64,
    /// (min, max) counts between index edges
    pub gap: Option<(i64, i64)>,
    pub cpr: Option<u32>,
}

/// Reads `ok encoder [ended] name=value ...`; None if it is not one.
pub fn parse_encoder(reply: &str) -> Option<EncoderFigures> {
    let rest = reply.strip_prefix("ok encoder")?;
    let f: BTreeMap<&str, &str> = rest.split_whitespace().filter_map(|w| w.split_once('=')).collect();
    let num = |k: &str| f.get(k).and_then(|v| v.parse::<i64>().ok());
    let gap = f.get("gap").and_then(|g| g.split_once("..")).and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?)));
    Some(EncoderFigures {
        moved: num("moved")?,
        backward: num("backward")? as u64,
        jumps: num("jumps")? as u64,
        chatter: num("chatter")? as u64,
        indexes: num("indexes")? as u64,
        gap,
        cpr: f.get("cpr").and_then(|v| v.parse().ok()),
    })
}

/// The cpr to set, or why none can be proposed. The index pulses' own
/// figure wins when the board measured one (the counts between two index
/// edges are exact; turns counted from a mark by hand are not); without
/// one, the counts over the turns given. Never a cpr the console refuses.
pub fn propose_cpr(f: &EncoderFigures, turns: Option<u32>) -> Result<u32, String> {
    if f.jumps > 0 {
        return Err(format!("{} jump(s) no lathe can make: noise on the encoder wires (shield them, check the ground) or max-rpm too low", f.jumps));
    }
    match (by_index(f), turns.filter(|&n| n > 0)) {
        (Some(indexed), _) => indexed,
        (None, Some(n)) => by_turns(f, n),
        (None, None) => Err(format!(
            "{} index pulse(s) seen: turn the chuck 3 turns or more one way, or give the number of turns (no index)",
            f.indexes
        )),
    }
}

/// The index pulses' figure, if the board measured one.
fn by_index(f: &EncoderFigures) -> Option<Result<u32, String>> {
    match (f.cpr, f.gap) {
        (Some(c), _) if CPR.contains(c) => Some(Ok(c)),
        (Some(c), _) => Some(Err(format!("the board reported cpr={c} between index pulses, which the console refuses ({}): a faulty board or encoder", CPR.allowed))),
        (None, Some((lo, hi))) if hi.saturating_sub(lo) > 1 => Some(Err(format!("counts between index pulses varied from {lo} to {hi}: counts are lost (noise, a loose coupling, or the lathe turned too fast for the encoder)"))),
        _ => None,
    }
}

/// The counts over `n` turns from a mark, to a whole cpr.
fn by_turns(f: &EncoderFigures, n: u32) -> Result<u32, String> {
    // Quadrature decoded ×4 makes 4 counts a line: the nearest multiple
    // of 4 to the counts a turn, which absorbs a hand's misalignment
    // of the mark by up to 2 counts a turn (the index check is exact).
    let counts = f.moved.unsigned_abs();
    let per_turn = (counts + 2 * n as u64) / (4 * n as u64) * 4;
    if per_turn == 0 {
        return Err(format!("{counts} counts in {n} turn(s): is the encoder connected?"));
    }
    match u32::try_from(per_turn).ok().filter(|&c| CPR.contains(c)) {
        Some(c) => Ok(c),
        None => Err(format!(
            "{counts} counts in {n} turn(s) is {per_turn} a turn, which the console's `cpr` refuses ({})",
            CPR.allowed
        )),
    }
}

/// When the index pulses and the turns counted both give a cpr and they
/// differ: said, with which is proposed (the index's).
pub fn disagreement(f: &EncoderFigures, turns: Option<u32>) -> Option<String> {
    let n = turns.filter(|&n| n > 0)?;
    let indexed = by_index(f)?.ok()?;
    match by_turns(f, n) {
        Ok(counted) if counted == indexed => None,
        Ok(counted) => Some(format!("the index pulses and the turns disagree: {n} turn(s) counted {counted} a turn, the index pulses {indexed}; the index's figure is proposed (were there exactly {n} turn(s) from the mark?)")),
        Err(why) => Some(format!("the index pulses and the turns disagree: {why}; the index's figure is proposed")),
    }
}

/// Motor steps per cutter turn: full steps × microsteps × the reduction
/// (motor turns per cutter turn, a fraction: 40/20 for a 20-tooth motor
/// pulley driving a 40-tooth one). Must come out whole, and in the
/// console's range for `steps`.
pub fn steps_per_cutter_turn(full_steps: u32, microsteps: u32, reduction: (u64, u64)) -> Result<u32, String> {
    let (n, d) = reduction;
    let total = full_steps as u64 * microsteps as u64 * n;
    if d == 0 || !total.is_multiple_of(d) {
        return Err(format!("{full_steps} x {microsteps} x {n}/{d} is not a whole number of steps per cutter turn: check the pulley teeth"));
    }
    let steps = total / d;
    match u32::try_from(steps).ok().filter(|&s| STEPS.contains(s)) {
        Some(s) => Ok(s),
        None => Err(format!(
            "{full_steps} x {microsteps} x {n}/{d} is {steps} steps per cutter turn: the console's `steps` takes {}",
            STEPS.allowed
        )),
    }
}

/// The `dir` setting that turns the cutter `wanted` relative to the
/// chuck: the gear's sign is the product of the encoder's (counts fall
/// for the lathe's forward turn: reversed), the motor's (a jog with
/// dir=same turned it against the chuck's forward turn: reversed), and
/// the setting's.
pub fn dir_setting(wanted: Sense, encoder_reversed: bool, motor_reversed: bool) -> Sense {
    let flip = encoder_reversed ^ motor_reversed;
    match (wanted, flip) {
        (Sense::Same, false) | (Sense::Opposite, true) => Sense::Same,
        _ => Sense::Opposite,
    }
}

/// Ratios a setup often uses, with the polygons they make (N = GR·Z).
pub const COMMON_RATIOS: &[(u32, u32, &str)] = &[
    (1, 1, "triangle (3 edges)"),
    (3, 2, "triangle (2 edges)"),
    (2, 1, "square (2 edges), hexagon (3 edges)"),
    (5, 2, "pentagon (2 edges)"),
    (3, 1, "hexagon (2 edges), nonagon (3 edges)"),
    (4, 1, "octagon (2 edges)"),
];

/// The fastest lathe rpm at ratio num/den: the motor's max-rate or the
/// lathe's max-rpm, whichever binds (rpm·GR·steps/60 ≤ max-rate).
pub fn fastest_lathe_rpm(c: &Config, num: u32, den: u32) -> u64 {
    let by_motor = c.max_step_rate_hz as u64 * 60 * den as u64 / (num as u64 * c.motor_steps_per_rev as u64).max(1);
    by_motor.min(c.max_lathe_rpm as u64)
}

/// Motor steps per lathe encoder count at the configured ratio, reduced.
pub fn steps_per_count(c: &Config) -> (u64, u64) {
    let n = c.ratio.num() as u64 * c.motor_steps_per_rev as u64;
    let d = c.ratio.den() as u64 * c.encoder_counts_per_rev as u64;
    let g = polyturn_sync::ratio::gcd(n, d).max(1);
    (n / g, d / g)
}

/// The settings as `get` reports them (`ok cpr=.. steps=.. ...`), read
/// back through the core's own `Config::with`, in an order in which each
/// fits the ones before: `get` lists max-rpm last, and a board at 11/3 with
/// max-rpm 600 has a ratio that does not fit the default max-rpm.
pub fn parse_settings(reply: &str) -> Option<Config> {
    let rest = reply.strip_prefix("ok ")?;
    let pairs: Vec<(String, String)> = rest
        .split_whitespace()
        .filter_map(|w| w.split_once('='))
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    send_order(&Config::default(), &pairs).ok().map(|(_, c)| c)
}

/// The order to send `changes` in so that each `set` is valid on the
/// board when it arrives (the board checks each against the others): each
/// step takes the first change the core's own `Config::with` accepts.
/// Returns the order and the settings it ends with.
pub type Order = (Vec<(String, String)>, Config);
pub fn send_order(from: &Config, changes: &[(String, String)]) -> Result<Order, String> {
    let (mut at, mut left, mut order) = (*from, changes.to_vec(), vec![]);
    while !left.is_empty() {
        let Some(i) = left.iter().position(|(n, v)| at.with(n, v).is_ok()) else {
            let (n, v) = &left[0];
            let e = at.with(n, v).err().map(|e| format!("{} {}", e.field, e.allowed)).unwrap_or_default();
            return Err(format!("these settings do not fit together: {e}"));
        };
        let (n, v) = left.remove(i);
        at = at.with(&n, &v).map_err(|e| format!("{} {}", e.field, e.allowed))?;
        order.push((n, v));
    }
    Ok((order, at))
}

#[cfg(test)]
#[path = "figures_tests.rs"]
mod tests;
