//! The book's generated pages (docs/src/generated/) are what the code says
//! today: the pin map, the LED codes, the console's words.

#[path = "../book/gen.rs"]
mod gen;

#[test]
fn the_committed_book_pages_match_the_code() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(gen::DIR);
    let mut stale = Vec::new();
    for (name, text) in gen::files() {
        let committed = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        if committed != text {
            stale.push(format!("{}/{name}", gen::DIR));
        }
    }
    assert!(stale.is_empty(), "{} differ from the code: run `{}` and commit them", stale.join(", "), gen::COMMAND);
}
