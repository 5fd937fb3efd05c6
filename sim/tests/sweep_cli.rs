//! `carfollow sweep` end to end on a tiny grid (runs of 1 s): a merge of shards equals an
//! unsharded run (wall-time fields aside, the figures are deterministic); a resume after a
//! killed run completes without redoing a point; bad input exits with status 2, naming the
//! bad axis path. Run with `cargo test --release -p sim --test sweep_cli`.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Two λ values × two seeds on `weave`, 1 s each: four points.
const TINY: &str = r#"
scenarios = ["SCENARIOS/weave.toml"]
seeds = [1, 2]
set = ["duration_s=1.0"]
[axes]
tracker.lambda = [0.6, 0.9]
"#;

fn sweep_file(dir: &Path, text: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    let path = dir.join("sweep.toml");
    std::fs::write(
        &path,
        text.replace("SCENARIOS", &root.display().to_string()),
    )
    .unwrap();
    path
}

fn carfollow(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .arg("--quiet")
        .output()
        .unwrap();
    out
}

fn ok(out: Output) -> Output {
    assert!(
        out.status.success(),
        "status {:?}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The rows of a results file, without the wall-clock fields that differ run to run.
fn rows(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| {
            let mut v: Value = serde_json::from_str(l).unwrap();
            let summary = v["summary"].as_object_mut().unwrap();
            summary.remove("wall_s");
            summary.remove("realtime_factor");
            v
        })
        .collect()
}

fn ids(path: &Path) -> Vec<String> {
    rows(path)
        .iter()
        .map(|r| r["id"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_merge_of_shards_equals_an_unsharded_run() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let whole = dir.path().join("whole");
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&whole),
        "--jobs",
        "2",
    ]));
    let mut shard_dirs = Vec::new();
    for i in 0..3 {
        let d = dir.path().join(format!("shard{i}"));
        ok(carfollow(&[
            "sweep",
            s(&sweep),
            "--out",
            s(&d),
            "--jobs",
            "1",
            "--shard",
            &format!("{i}/3"),
        ]));
        assert!(d.join(format!("results-shard-{i}-of-3.jsonl")).exists());
        shard_dirs.push(d);
    }
    let merged = dir.path().join("merged");
    let mut args = vec!["sweep", "merge"];
    args.extend(shard_dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(&merged)]);
    ok(Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(&args)
        .output()
        .unwrap());

    let a = rows(&whole.join("results.jsonl"));
    // The unsharded file is in finishing order; the merged one in grid order.
    let mut a_sorted = a.clone();
    a_sorted.sort_by_key(|r| r["index"].as_u64());
    let b = rows(&merged.join("results.jsonl"));
    assert_eq!(a.len(), 4);
    assert_eq!(a_sorted, b);
    for f in ["table.csv", "summary.md", "sweep-tracker.lambda.png"] {
        assert!(merged.join(f).exists(), "{f}");
        assert!(whole.join(f).exists(), "{f}");
    }
}

#[test]
fn a_resume_after_a_kill_completes_without_redoing_points() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let out = dir.path().join("out");
    // The "killed" run: only half the grid finished, and the last line was cut mid-write.
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--shard",
        "0/2",
    ]));
    let shard_file = out.join("results-shard-0-of-2.jsonl");
    let done = std::fs::read_to_string(&shard_file).unwrap();
    let mut lines: Vec<&str> = done.lines().collect();
    assert_eq!(lines.len(), 2);
    let cut = lines.pop().unwrap();
    let kept = lines[0].to_string();
    let results = out.join("results.jsonl");
    std::fs::write(&results, format!("{kept}\n{}", &cut[..cut.len() / 2])).unwrap();

    // Without --resume, the results are not overwritten.
    let refused = carfollow(&["sweep", s(&sweep), "--out", s(&out)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--resume"));

    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--resume",
    ]));
    let text = std::fs::read_to_string(&results).unwrap();
    // The finished point was not run again: its line is byte-identical (its wall time
    // would differ) and comes first.
    assert!(text.starts_with(&format!("{kept}\n")), "{text}");
    let mut got = ids(&results);
    assert_eq!(got.len(), 4, "{text}");
    got.sort();
    got.dedup();
    assert_eq!(got.len(), 4, "a point ran twice: {text}");

    // A second resume has nothing left to do.
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--resume",
    ]));
    assert_eq!(std::fs::read_to_string(&results).unwrap(), text);
}

#[test]
fn bad_input_exits_2_naming_the_axis_path() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), &TINY.replace("tracker.lambda", "tracker.lamda"));
    let out = carfollow(&["sweep", s(&sweep), "--out", s(&dir.path().join("out"))]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("tracker.lamda"), "{err}");
    assert!(!dir.path().join("out/results.jsonl").exists());

    let sweep = sweep_file(dir.path(), TINY);
    for shard in ["2/2", "1-of-2"] {
        let out = carfollow(&["sweep", s(&sweep), "--shard", shard]);
        assert_eq!(out.status.code(), Some(2), "--shard {shard}");
    }
    let out = carfollow(&["sweep", s(&dir.path().join("missing.toml"))]);
    assert_eq!(out.status.code(), Some(2));
}
