//! Compiles the shipped scenario library (`scenarios/*.toml`, `scenarios/targets/*.toml`
//! and the OpenDRIVE roads `scenarios/roads/*.xodr`)
//! into the library, so that a scenario can be named (`nist-grounds`, `weave`) from any
//! folder, and from the Python package, wherever it is installed.

use std::fmt::Write as _;
use std::path::Path;

/// `(name, absolute path)` of the files in `dir` ending `.{extension}`, sorted by name.
fn files(dir: &Path, extension: &str) -> Vec<(String, String)> {
    let mut found: Vec<(String, String)> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == extension))
                .filter_map(|p| {
                    let name = p.file_stem()?.to_str()?.to_string();
                    let path = p.canonicalize().ok()?.to_str()?.to_string();
                    Some((name, path))
                })
                .collect()
        })
        .unwrap_or_default();
    found.sort();
    found
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let targets = root.join("targets");
    let roads = root.join("roads");
    println!("cargo:rerun-if-changed={}", root.display());
    println!("cargo:rerun-if-changed={}", targets.display());
    println!("cargo:rerun-if-changed={}", roads.display());
    let mut out = String::new();
    for (list, dir, extension) in [
        ("SCENARIOS", &root, "toml"),
        ("TARGETS", &targets, "toml"),
        ("ROADS", &roads, "xodr"),
    ] {
        let _ = writeln!(out, "pub(crate) const {list}: &[(&str, &str)] = &[");
        for (name, path) in files(dir, extension) {
            println!("cargo:rerun-if-changed={path}");
            let _ = writeln!(out, "    ({name:?}, include_str!({path:?})),");
        }
        let _ = writeln!(out, "];");
    }
    let to = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("library.rs");
    std::fs::write(to, out).expect("OUT_DIR is writable");
}
