//! Prints, as JSON, the register values `board.rs` implies, for `.ci/emu`
//! to compare with what the real image writes in the emulator: each pin's
//! GPIO MODER/AFR/PUPDR fields, each interrupt's NVIC priority byte (the
//! level in the top 4 bits, PM0214 §4.3.7), the tick rate, the system
//! clock, the ESC's stop pulse and ENABLE's default polarity.
//! Run: cargo run -q -p polyturn-firmware --example expected_registers

use polyturn_firmware::board;

fn main() {
    let mut out = String::from("{\n");
    out += &format!("  \"sysclk_hz\": {},\n  \"tick_hz\": {},\n", board::SYSCLK_HZ, board::TICK_HZ);
    // the safe states the E-stop check expects: the ESC's stop pulse, and
    // ENABLE's polarity with default settings (the emulator's flash is erased)
    out += &format!("  \"esc_stop_us\": {},\n", polyturn_firmware::esc::STOP_US);
    let active_high = polyturn_sync::Config::default().enable_active_high;
    out += &format!("  \"enable_active_high\": {},\n", active_high);
    out += "  \"pins\": [\n";
    let pins: Vec<String> = board::PINS
        .iter()
        .map(|p| {
            let (port, index) = p.port_and_index();
            let af = p.mode.af().map_or("null".to_string(), |n| n.to_string());
            format!(
                "    {{\"signal\": \"{}\", \"pin\": \"{}\", \"port\": \"{}\", \"index\": {}, \"moder\": {}, \"afr\": {}, \"pupdr\": {}}}",
                p.signal,
                p.pin,
                port,
                index,
                p.mode.moder(),
                af,
                p.pull.pupdr()
            )
        })
        .collect();
    out += &pins.join(",\n");
    out += "\n  ],\n  \"priorities\": [\n";
    let prios: Vec<String> = board::PRIORITIES
        .iter()
        .map(|(name, level)| {
            format!("    {{\"name\": \"{}\", \"level\": {}, \"ipr\": {}}}", name, level, (*level as u32) << 4)
        })
        .collect();
    out += &prios.join(",\n");
    out += "\n  ]\n}";
    println!("{out}");
}
