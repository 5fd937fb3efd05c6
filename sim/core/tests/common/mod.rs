//! What the scenario-file tests share: the shipped scenarios' folder, the NIST scenario's
//! text, and loading a text as `carfollow check` does.

#![allow(dead_code)]

use sim_core::{Plan, Scenario};
use std::path::{Path, PathBuf};

pub fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

pub fn text() -> String {
    std::fs::read_to_string(scenarios_dir().join("nist-grounds.toml")).unwrap()
}

/// Loads and plans `text` as if it were `scenarios/bad.toml` (as `carfollow check` does):
/// the scenario planned.
pub fn load(text: &str, overrides: &[&str]) -> Result<Scenario, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    std::fs::create_dir(dir.path().join("targets")).unwrap();
    std::fs::copy(
        scenarios_dir().join("targets/nist-ten-segment.toml"),
        dir.path().join("targets/nist-ten-segment.toml"),
    )
    .unwrap();
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Plan::load(&path, &overrides)
        .map(|plan| plan.scenario().clone())
        .map_err(|e| {
            // Errors are reported relative to the file name for the assertions below.
            e.to_string().replace(&dir.path().display().to_string(), "")
        })
}

/// 1-based line of the first occurrence of `needle` in the shipped text.
pub fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}
