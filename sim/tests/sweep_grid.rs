//! Sweep grids, without running anything: the shards of a grid cover every point exactly
//! once for several N; ids are unique and stable; the shipped sweeps validate; a bad axis
//! path or an unknown field is refused, naming the path and where it is.
//! Run with `cargo test -p sim --test sweep_grid`.

use sim::{Shard, Sweep};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios")
}

/// Writes `text` as `sweep.toml` in a fresh folder; `SCENARIOS` in it becomes the absolute
/// path of the shipped scenarios folder.
fn sweep_file(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sweep.toml");
    let root = scenarios_dir().display().to_string();
    std::fs::write(&path, text.replace("SCENARIOS", &root)).unwrap();
    (dir, path)
}

const GRID: &str = r#"
scenarios = ["SCENARIOS/weave.toml", "SCENARIOS/hard-braking.toml"]
seeds = [1, 2, 3]
set = ["duration_s=1.0"]
[axes]
tracker.lambda = { from = 0.5, to = 0.98, step = 0.04 }
environment.sun.strength = [0.5, 1.0]
"#;

#[test]
fn shards_cover_every_point_exactly_once() {
    let (_dir, path) = sweep_file(GRID);
    let sweep = Sweep::load(&path, &[]).unwrap();
    assert_eq!(sweep.points.len(), 2 * 3 * 13 * 2);
    for count in [1, 2, 3, 4, 7, 200] {
        let mut seen: BTreeMap<usize, usize> = BTreeMap::new();
        for index in 0..count {
            let shard = Some(Shard { index, count });
            for p in sweep.shard(shard) {
                *seen.entry(p.index).or_default() += 1;
            }
        }
        assert_eq!(seen.len(), sweep.points.len(), "N = {count}: points missed");
        assert!(
            seen.values().all(|&n| n == 1),
            "N = {count}: a point ran twice"
        );
    }
}

#[test]
fn ids_are_unique_and_stable() {
    let (_dir, path) = sweep_file(GRID);
    let a = Sweep::load(&path, &[]).unwrap();
    let b = Sweep::load(&path, &[]).unwrap();
    assert_eq!(a.points, b.points);
    let mut ids: Vec<&str> = a.points.iter().map(|p| p.id.as_str()).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), a.points.len());
    // The grid order: scenario, then the axes (sorted by path, first outermost), seed last.
    let p = &a.points[1];
    assert_eq!(
        p.describe(),
        "weave seed=2 environment.sun.strength=0.5 tracker.lambda=0.5"
    );
    assert_eq!(
        a.points.last().unwrap().describe(),
        "hard-braking seed=3 environment.sun.strength=1.0 tracker.lambda=0.98"
    );
    // A different experiment (other common overrides) gets other ids.
    let c = Sweep::load(&path, &["duration_s=2.0".into()]).unwrap();
    assert_ne!(a.points[0].id, c.points[0].id);
}

#[test]
fn the_shipped_sweeps_validate() {
    let dir = scenarios_dir().join("sweeps");
    let lambda = Sweep::load(&dir.join("lambda.toml"), &[]).unwrap();
    assert_eq!(lambda.points.len(), 13 * 3 * 4);
    let smoke = Sweep::load(&dir.join("smoke.toml"), &[]).unwrap();
    assert_eq!(smoke.points.len(), 2);
    // Every sweep shipped loads, with points.
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "{files:?}");
    for file in files {
        let sweep = Sweep::load(&file, &[]).unwrap_or_else(|e| panic!("{e}"));
        assert!(!sweep.points.is_empty(), "{}", file.display());
    }
}

#[test]
fn a_bad_axis_path_is_refused_naming_it() {
    let (_dir, path) = sweep_file(
        "scenarios = [\"SCENARIOS/weave.toml\"]\nseeds = [1]\n[axes]\ntracker.lamda = [0.5]\n",
    );
    let err = Sweep::load(&path, &[]).unwrap_err().to_string();
    assert!(err.contains("tracker.lamda"), "{err}");
    assert!(err.contains("sweep.toml:4:"), "{err}");
    assert!(err.contains("unknown field `lamda`"), "{err}");
}

/// A field of the wrong type is named, with its line, as a scenario's would be.
#[test]
fn a_field_of_the_wrong_type_is_refused_naming_it() {
    let head = "scenarios = [\"SCENARIOS/weave.toml\"]\n";
    for (body, needle) in [
        (
            "seeds = [1]\n[set]\nduration_s = 6\n[axes]\ntracker.lambda = [0.5]\n",
            "sweep.toml:3:1: `set`: invalid type: map, expected a sequence",
        ),
        (
            "seeds = [1, \"a\"]\n[axes]\ntracker.lambda = [0.5]\n",
            "sweep.toml:2:13: `seeds[1]`: invalid type: string \"a\"",
        ),
    ] {
        let (_dir, path) = sweep_file(&format!("{head}{body}"));
        let err = Sweep::load(&path, &[]).unwrap_err().to_string();
        assert!(err.contains(needle), "{err}");
    }
}

#[test]
fn a_bad_axis_value_is_refused_naming_it() {
    let (_dir, path) = sweep_file(
        "scenarios = [\"SCENARIOS/weave.toml\"]\nseeds = [1]\n[axes]\ntracker.lambda = [0.5, 7.0]\n",
    );
    let err = Sweep::load(&path, &[]).unwrap_err().to_string();
    assert!(err.contains("tracker.lambda=7.0"), "{err}");
}

/// A value listed twice would make two points of one id; a field both swept and set in
/// `set` or `--set` would lose the setting without a word. A table set with the swept
/// field inside it is fine.
#[test]
fn repeated_values_and_settings_an_axis_overrides_are_refused() {
    let head = "scenarios = [\"SCENARIOS/weave.toml\"]\nseeds = [1]\n";
    let (_dir, path) = sweep_file(&format!("{head}[axes]\ntracker.lambda = [0.5, 0.5]\n"));
    let err = Sweep::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("`axes.tracker.lambda`") && err.contains("lists 0.5 twice"),
        "{err}"
    );
    let axis = "[axes]\ntracker.lambda = [0.5, 0.6]\n";
    let (_dir, path) = sweep_file(&format!("{head}set = [\"tracker.lambda=0.7\"]\n{axis}"));
    let err = Sweep::load(&path, &[]).unwrap_err().to_string();
    assert!(err.contains("`set`") && err.contains("sweeps"), "{err}");
    let (_dir, path) = sweep_file(&format!("{head}{axis}"));
    let err = Sweep::load(&path, &["tracker.lambda=0.8".into()])
        .unwrap_err()
        .to_string();
    assert!(err.contains("tracker.lambda=0.8"), "{err}");
    let err = Sweep::load(&path, &["seed=4".into()])
        .unwrap_err()
        .to_string();
    assert!(err.contains("list seeds in `seeds`"), "{err}");
    // A table set, with the swept field inside it.
    let (_dir, path) = sweep_file(&format!(
        "{head}set = [\"environment.sun={{ elevation_deg = 30.0 }}\"]\n[axes]\nenvironment.sun.strength = [0.5, 1.0]\n"
    ));
    Sweep::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn unknown_fields_and_bad_ranges_are_refused_with_position() {
    let (_dir, path) =
        sweep_file("scenarios = [\"SCENARIOS/weave.toml\"]\nseeds = [1]\nseed = 3\n");
    let err = Sweep::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("sweep.toml:3:1") && err.contains("unknown field `seed`"),
        "{err}"
    );

    let (_dir, path) = sweep_file(
        "scenarios = [\"SCENARIOS/weave.toml\"]\nseeds = [1]\n[axes]\ntracker.lambda = { from = 0.9, to = 0.5, step = 0.1 }\n",
    );
    let err = Sweep::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("sweep.toml:4:") && err.contains("`axes.tracker.lambda`"),
        "{err}"
    );
}
