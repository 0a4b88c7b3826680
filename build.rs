//! Build script: a hash of the crate's source (`src/**`, `Cargo.toml`, `Cargo.lock`), exposed
//! as `CWSYNTH_SOURCE_HASH`. `cwsynth batch` mixes it into each machine's input hash, so a
//! re-run after the program changed re-solves instead of keeping results computed by the
//! old code (FNV-1a, 64 bit, over the sorted file paths and contents: stable across builds
//! and Rust versions).

use std::path::{Path, PathBuf};

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else {
                out.push(p);
            }
        }
    }
}

fn main() {
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=Cargo.toml");
    println!("cargo:rerun-if-changed=Cargo.lock");
    let mut files = vec![PathBuf::from("Cargo.toml"), PathBuf::from("Cargo.lock")];
    walk(Path::new("src"), &mut files);
    files.sort();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &x in bytes {
            h = (h ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for f in &files {
        eat(f.to_string_lossy().replace('\\', "/").as_bytes());
        eat(b"\0");
        eat(&std::fs::read(f).unwrap_or_default());
        eat(b"\0");
    }
    println!("cargo:rustc-env=CWSYNTH_SOURCE_HASH={h:016x}");
}
