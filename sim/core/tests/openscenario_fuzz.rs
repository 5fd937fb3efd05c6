//! Mutated OpenSCENARIO files: 300 mutants of `tests/data/openscenario/cut-in.xosc`
//! (attribute values changed to garbage, huge, negative or not-a-number values, elements
//! deleted or repeated, the text cut short) are read without a panic or a hang, each
//! refusal is one line naming the file and its line (or the road file's), and every mutant
//! that is read and planned (what `carfollow check` accepts) runs: its loop is built and
//! steps one simulated second (what `carfollow run` does).
//!
//! `cargo test --release -p sim-core --test openscenario_fuzz`.

use rand::{Rng, SeedableRng};
use sim_core::openscenario::ImportOptions;
use sim_core::{ClosedLoop, Plan, Scenario};
use sim_render::Backend;
use std::path::{Path, PathBuf};

/// Mutants read.
const MUTANTS: usize = 300;

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/openscenario")
}

/// The file's text with one mutation drawn from `rng`.
fn mutate(text: &str, rng: &mut rand_chacha::ChaCha8Rng) -> String {
    // Attribute values: `="..."`.
    let values: Vec<(usize, usize)> = text
        .match_indices("=\"")
        .filter_map(|(i, _)| {
            let start = i + 2;
            text[start..].find('"').map(|len| (start, start + len))
        })
        .collect();
    let lines: Vec<&str> = text.lines().collect();
    match rng.random_range(0..6) {
        0..=2 => {
            let (a, b) = values[rng.random_range(0..values.len())];
            let replacement = [
                "",
                "abc",
                "-1",
                "-1e9",
                "1e308",
                "NaN",
                "inf",
                "0",
                "$Nope",
                "${1/0}",
                "${pow(10, 400)}",
                "${$LeadSpeed * 100}",
                "-2",
                "7",
                "Ego",
                "Cutter",
                "99",
                "${(((1)}",
            ][rng.random_range(0..18)];
            format!("{}{}{}", &text[..a], replacement, &text[b..])
        }
        3 => {
            // A line deleted.
            let k = rng.random_range(0..lines.len());
            lines
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != k)
                .map(|(_, l)| *l)
                .collect::<Vec<_>>()
                .join("\n")
        }
        4 => {
            // A line repeated.
            let k = rng.random_range(0..lines.len());
            let mut out: Vec<&str> = lines.clone();
            out.insert(k, lines[k]);
            out.join("\n")
        }
        _ => {
            // Cut short.
            let mut cut = rng.random_range(0..text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text[..cut].to_string()
        }
    }
}

#[test]
fn mutated_files_are_refused_in_one_line_or_run() {
    let dir = tempfile::tempdir().unwrap();
    for entry in walk(&data()) {
        let to = dir.path().join(entry.strip_prefix(data()).unwrap());
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(&entry, &to).unwrap();
    }
    let original = std::fs::read_to_string(data().join("cut-in.xosc")).unwrap();
    let path = dir.path().join("mutant.xosc");
    let backend = Backend::choose(None).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(49);
    let (mut refused, mut ran) = (0, 0);
    for k in 0..MUTANTS {
        let text = mutate(&original, &mut rng);
        std::fs::write(&path, &text).unwrap();
        let options = ImportOptions::default();
        let planned = Scenario::load_openscenario(&path, &["duration_s=1".into()], &options)
            .map_err(|e| e.to_string())
            .and_then(|s| Plan::new(&s).map_err(|e| e.to_string()));
        match planned {
            Err(message) => {
                assert!(
                    !message.contains('\n'),
                    "mutant {k}: more than one line: {message}"
                );
                assert!(
                    message.contains("mutant.xosc")
                        || message.contains(".xodr")
                        || message.contains("catalogs"),
                    "mutant {k}: the error names no file: {message}"
                );
                refused += 1;
            }
            Ok(plan) => {
                let mut looped = ClosedLoop::new(plan, backend, false).unwrap_or_else(|e| {
                    panic!("mutant {k} was planned, but the loop refused it: {e}\n{text}")
                });
                let mut frames = 0;
                while let Some(out) = looped.step().unwrap_or_else(|e| panic!("mutant {k}: {e}")) {
                    assert!(out.record.t_s.is_finite());
                    frames += 1;
                }
                assert_eq!(frames, 15, "mutant {k}");
                ran += 1;
            }
        }
    }
    eprintln!("{refused} mutants refused, {ran} ran");
    assert!(
        refused > 0 && ran > 0,
        "both sides of the property are tested"
    );
}

/// Every file under `dir`.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}
