//! The fake board (`polyturn_bench::fakeboard`) on stdin and stdout: each
//! read of stdin is one write to the board (so a writer's pauses split it
//! as they would split writes to a port), its replies go to stdout as they
//! come. `.ci/emu-device` sends the firmware's hostile lines through this
//! and through the emulated board and compares the two. By hand:
//! `cargo run -p polyturn-bench --bin fake-board`, then type console
//! lines (`status`, `set ratio 11/3`, `#7 get ratio`).
use polyturn_bench::fakeboard::FakeDevice;
use std::io::{Read, Write};

fn main() -> std::io::Result<()> {
    let mut dev = FakeDevice::new();
    let (mut input, mut out) = (std::io::stdin().lock(), std::io::stdout().lock());
    let mut buf = [0u8; 4096];
    loop {
        let n = input.read(&mut buf)?;
        if n == 0 {
            return Ok(());
        }
        dev.write_all(&buf[..n])?;
        out.write_all(&dev.take_replies())?;
        out.flush()?;
    }
}
