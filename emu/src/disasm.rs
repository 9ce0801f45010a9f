//! The addresses of wfe/sev/wfi/udf/cpsid i/cpsie i/msr primask in the image, from
//! llvm-objdump (rustup's llvm-tools), which uses the ELF's mapping symbols to tell
//! code from literal pools.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The addresses of the instructions the harness treats specially.
#[derive(Default)]
pub struct Insns {
    pub wfe: Vec<u32>,
    pub sev: Vec<u32>,
    pub wfi: Vec<u32>,
    pub udf: Vec<u32>,
    pub cpsid: Vec<u32>,
    pub cpsie: Vec<u32>,
    pub msr_primask: Vec<u32>,
    pub msr_basepri: Vec<u32>,
}

fn objdump() -> Result<PathBuf, String> {
    let out = Command::new("rustc").args(["--print", "sysroot"]).output().map_err(|e| format!("rustc: {e}"))?;
    let root = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    let lib = root.join("lib/rustlib");
    for e in std::fs::read_dir(&lib).map_err(|e| format!("{}: {e}", lib.display()))?.flatten() {
        let p = e.path().join("bin/llvm-objdump");
        if p.exists() {
            return Ok(p);
        }
    }
    Err("no llvm-objdump under the rust sysroot (rustup component add llvm-tools)".into())
}

/// `llvm-objdump -d` of the image with the raw bytes shown (what
/// `cycles::program::Program::parse` and `scan` read).
pub fn text(elf: &Path) -> Result<String, String> {
    let out = Command::new(objdump()?).arg("-d").arg(elf).output().map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!("llvm-objdump -d {}: {}", elf.display(), String::from_utf8_lossy(&out.stderr).trim()));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The instructions the harness treats specially, from `text`'s listing: a
/// code line is `addr: <halfwords>\t<mnemonic>\t<operands>`.
pub fn scan(listing: &str) -> Insns {
    let mut found = Insns::default();
    for line in listing.lines() {
        let Some((addr, rest)) = line.trim_start().split_once(':') else { continue };
        let Ok(addr) = u32::from_str_radix(addr, 16) else { continue };
        let Some((_, text)) = rest.split_once('\t') else { continue };
        let mut words = text.split_whitespace();
        let (op, args) = (words.next().unwrap_or(""), words.collect::<Vec<_>>().join(" ").to_lowercase());
        match op {
            "wfe" => found.wfe.push(addr),
            "sev" => found.sev.push(addr),
            "wfi" => found.wfi.push(addr),
            "udf" => found.udf.push(addr),
            "cpsid" if args.starts_with('i') => found.cpsid.push(addr),
            "cpsie" if args.starts_with('i') => found.cpsie.push(addr),
            "msr" if args.starts_with("primask") => found.msr_primask.push(addr),
            "msr" if args.starts_with("basepri") => found.msr_basepri.push(addr),
            _ => {}
        }
    }
    found
}
