//! Writes the book's generated pages (docs/src/generated/) from the code
//! that holds each fact: `cargo run -p polyturn-firmware --example book`.
//! `firmware/tests/book.rs` checks the committed files against them.

#[path = "../book/gen.rs"]
mod gen;

fn main() -> std::io::Result<()> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = root.join(gen::DIR);
    std::fs::create_dir_all(&dir)?;
    for (name, text) in gen::files() {
        std::fs::write(dir.join(name), text)?;
        println!("wrote {}/{name}", gen::DIR);
    }
    println!("commit them: `cargo test` compares them with what `{}` writes", gen::COMMAND);
    Ok(())
}
