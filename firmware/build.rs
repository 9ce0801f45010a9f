//! Relinks the firmware when the workspace's `memory.x` changes (cortex-m-rt
//! finds it on the linker's search path, so cargo does not track it).
fn main() {
    println!("cargo:rerun-if-changed=../memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
