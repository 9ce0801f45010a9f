//! With the `embed` feature, compiles into `polyturn` the page (web/www,
//! with the pkg/ that `bash web/build` makes) and the release firmware
//! image (target/release-image, from `cargo fw && bash .ci/release-image`),
//! so that a release binary needs no checkout. Without the feature it does
//! nothing: a fresh clone's `cargo build` and `cargo test` need neither.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_EMBED").is_none() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap_or(Path::new(".."));
    let page = root.join("web/www");
    let name = format!("polyturn-{}-stm32f411ce.bin", env!("CARGO_PKG_VERSION"));
    let firmware = root.join("target/release-image").join(&name);
    // a directory is scanned whole: any file added or rebuilt in it counts
    println!("cargo:rerun-if-changed={}", page.display());
    println!("cargo:rerun-if-changed={}", firmware.display());
    let mut missing = Vec::new();
    if !page.join("pkg/polyturn_web_bg.wasm").is_file() {
        missing.push(format!("the page ({}/pkg is not built): run `bash web/build`", page.display()));
    }
    if !firmware.is_file() {
        missing.push(format!(
            "the firmware ({} is missing): run `cargo fw && bash .ci/release-image`",
            firmware.display()
        ));
    }
    if !missing.is_empty() {
        fail(&format!("the `embed` feature needs {}", missing.join("; and ")));
    }
    let mut files = Vec::new();
    walk(&page, &page, &mut files);
    files.sort();
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default()).join("embedded.rs");
    if let Err(e) = std::fs::write(&out, source(&files, &name, &firmware)) {
        fail(&format!("cannot write {}: {e}", out.display()));
    }
}

/// Stops the build with one message (a panic would bury it in a backtrace hint).
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

/// The page's regular files under `dir`, as (name with '/', full path);
/// names starting with '.' are left out, as the server refuses them.
fn walk(root: &Path, dir: &Path, files: &mut Vec<(String, PathBuf)>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", dir.display())));
    for entry in entries.flatten() {
        let path = entry.path();
        if entry.file_name().as_encoded_bytes().starts_with(b".") {
            continue;
        }
        if path.is_dir() {
            walk(root, &path, files);
        } else if path.is_file() {
            let rel = path.strip_prefix(root).unwrap_or(&path);
            let parts: Option<Vec<&str>> = rel.components().map(|c| c.as_os_str().to_str()).collect();
            let name = parts.unwrap_or_else(|| fail(&format!("{} is not a UTF-8 name", path.display())));
            files.push((name.join("/"), path));
        }
    }
}

/// The generated module: the page as (name, bytes) and the image.
fn source(files: &[(String, PathBuf)], name: &str, firmware: &Path) -> String {
    let mut s = String::from("pub static PAGE: &[(&str, &[u8])] = &[\n");
    for (rel, path) in files {
        let _ = writeln!(s, "    ({rel:?}, include_bytes!({:?})),", text(path));
    }
    s.push_str("];\n");
    let _ = writeln!(s, "pub static FIRMWARE: (&str, &[u8]) = ({name:?}, include_bytes!({:?}));", text(firmware));
    s
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap_or_else(|| fail(&format!("{} is not a UTF-8 path", path.display())))
}
