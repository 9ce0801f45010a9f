//! Writes the spindle chapter's tables (docs/src/generated/spindle-*.md) from
//! the geometry model: `cargo run -p polyturn-host --example spindle_book`.
//! `the_spindle_tables_in_the_book_match_the_model` fails when they are stale.

fn main() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/src/generated");
    for (name, text) in polyturn_host::geometry::alignment::book_pages() {
        std::fs::write(dir.join(name), text).expect("docs/src/generated is writable");
        println!("wrote docs/src/generated/{name}");
    }
}
