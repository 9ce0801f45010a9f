//! Prints, as JSON, the register values `board.rs` implies, for `.ci/emu`
//! to compare with what the real image writes in the emulator: each pin's
//! GPIO MODER/AFR/PUPDR fields, each interrupt's NVIC priority byte (the
//! level in the top 4 bits, PM0214 §4.3.7), the tick rate and the system
//! clock. Run: cargo run -q -p polyturn-firmware --example expected_registers

use polyturn_firmware::board;

fn main() {
    let mut out = String::from("{\n");
    out += &format!("  \"sysclk_hz\": {},\n  \"tick_hz\": {},\n", board::SYSCLK_HZ, board::TICK_HZ);
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
        .map(|(name, level)| format!("    {{\"name\": \"{}\", \"level\": {}, \"ipr\": {}}}", name, level, (*level as u32) << 4))
        .collect();
    out += &prios.join(",\n");
    out += "\n  ]\n}";
    println!("{out}");
}
