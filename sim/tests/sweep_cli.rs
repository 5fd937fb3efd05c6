//! `carfollow sweep` end to end on a tiny grid (runs of 1 s): a merge of shards equals an
//! unsharded run (wall-time fields aside, the figures are deterministic); a resume after a
//! killed run completes without redoing a point; bad input exits with status 2, naming the
//! bad axis path; a worker process that dies costs only its point; Ctrl-C keeps every
//! finished row and `--resume` finishes the rest; `--jobs 0` and a merge of an empty folder
//! are refused; a merge lists the grid's missing points and exits 3; `--resume` refuses
//! results of a changed sweep file or other overrides; an output folder that cannot be made
//! exits 3. Run with
//! `cargo test --release -p sim --test sweep_cli`.

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

/// The rows of a results file, without the wall-clock fields that differ run to run
/// (`wall_s`, `realtime_factor`, `timing`).
fn rows(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| {
            let mut v: Value = serde_json::from_str(l).unwrap();
            let summary = v["summary"].as_object_mut().unwrap();
            summary.remove("wall_s");
            summary.remove("realtime_factor");
            summary.remove("timing");
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

    // Merging into a folder that holds other results would overwrite them: refused.
    let before = std::fs::read(whole.join("results.jsonl")).unwrap();
    let mut args = vec!["sweep", "merge"];
    args.extend(shard_dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(&whole)]);
    let o = carfollow(&args);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("already holds sweep results"));
    assert_eq!(std::fs::read(whole.join("results.jsonl")).unwrap(), before);

    let a = rows(&whole.join("results.jsonl"));
    // The unsharded file is in finishing order; the merged one in grid order.
    let mut a_sorted = a.clone();
    a_sorted.sort_by_key(|r| r["index"].as_u64());
    let b = rows(&merged.join("results.jsonl"));
    assert_eq!(a.len(), 4);
    assert_eq!(a_sorted, b);
    // Each row says what its point changed of the scenario file.
    for r in &a {
        let overrides: Vec<&str> = r["summary"]["overrides"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert!(
            overrides.iter().any(|o| o.starts_with("seed="))
                && overrides.iter().any(|o| o.starts_with("tracker.lambda=")),
            "{overrides:?}"
        );
    }
    for f in ["table.csv", "summary.md", "sweep-tracker.lambda.png"] {
        assert!(merged.join(f).exists(), "{f}");
        assert!(whole.join(f).exists(), "{f}");
    }
}

/// Runs `--resume` on `out`, checks that the results still start with `kept` (finished rows
/// are not rewritten) and now hold `points` distinct points; returns them.
fn resume_completes(sweep: &Path, out: &Path, kept: &str, points: usize) -> String {
    ok(carfollow(&["sweep", s(sweep), "--out", s(out), "--resume"]));
    let results = out.join("results.jsonl");
    let text = std::fs::read_to_string(&results).unwrap();
    assert!(
        text.starts_with(kept),
        "finished rows were rewritten: {text}"
    );
    let mut got = ids(&results);
    assert_eq!(got.len(), points, "{text}");
    got.sort();
    got.dedup();
    assert_eq!(got.len(), points, "a point ran twice: {text}");
    text
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

    // The finished point was not run again: its line is byte-identical (its wall time
    // would differ) and comes first.
    let text = resume_completes(&sweep, &out, &format!("{kept}\n"), 4);

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

    // The pre-flight is the scenario's own validation: what the closed loop would refuse
    // at its start is refused before any point runs, naming the override.
    let sweep = sweep_file(
        dir.path(),
        &TINY.replace("set = [", "set = [\"lead.start_m=0\", "),
    );
    let out_dir = dir.path().join("preflight");
    let out = carfollow(&["sweep", s(&sweep), "--out", s(&out_dir)]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--set lead.start_m=0: `lead.start_m` puts the chase vehicle"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!out_dir.exists());
}

/// A worker command that runs `script` in `sh` before (maybe) becoming a real worker.
fn shell_worker(script: String) -> impl Fn() -> Command + Sync {
    move || {
        let mut c = Command::new("sh");
        c.arg("-c").arg(&script);
        c
    }
}

#[test]
fn a_worker_that_dies_costs_only_its_point() {
    use sim::{read_rows, run_points, ResultsWriter, Sweep};
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(dir.path(), TINY);
    let sweep = Sweep::load(&file, &[]).unwrap();
    let points = sweep.shard(None);
    let results = dir.path().join("results.jsonl");

    // Every worker dies on its first point: every point fails, nothing is written, and the
    // errors name the points in grid order.
    let writer = ResultsWriter::open(&results, None).unwrap();
    let dying = shell_worker("read request; kill -9 $$".into());
    let errors = run_points(&points, 2, &dying, &writer, |_| {}).unwrap();
    assert_eq!(errors.len(), 4);
    for (e, p) in errors.iter().zip(&points) {
        let e = e.to_string();
        assert!(e.contains(&p.describe()) && e.contains("died"), "{e}");
        // The point is named once.
        assert_eq!(e.matches(&p.describe()).count(), 1, "{e}");
    }
    assert!(read_rows(&results).unwrap().0.is_empty());

    // The first worker dies; the next one started is a real worker and runs the rest.
    let marker = dir.path().join("died-once");
    let writer = ResultsWriter::open(&results, None).unwrap();
    let once = shell_worker(format!(
        "if [ ! -e '{m}' ]; then touch '{m}'; read request; kill -9 $$; fi; exec '{exe}' sweep-worker '{f}'",
        m = marker.display(),
        exe = env!("CARGO_BIN_EXE_carfollow"),
        f = file.display()
    ));
    let errors = run_points(&points, 1, &once, &writer, |_| {}).unwrap();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].to_string().contains(&points[0].describe()));
    let (rows, _) = read_rows(&results).unwrap();
    let mut done: Vec<usize> = rows.iter().map(|r| r.index).collect();
    done.sort();
    assert_eq!(done, vec![1, 2, 3]);
}

#[cfg(target_os = "linux")]
#[test]
fn ctrl_c_keeps_every_finished_row_and_resume_finishes_the_rest() {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    // Eight points: four of 1 s, then four of 120 s (the first axis varies slowest), so that
    // the interrupt, sent once two rows are in, finds the long points running however slowly
    // a loaded machine sends it.
    let sweep = sweep_file(
        dir.path(),
        r#"
scenarios = ["SCENARIOS/weave.toml"]
seeds = [1, 2, 3, 4]
[axes]
duration_s = [1.0, 120.0]
"#,
    );
    let out = dir.path().join("out");
    let results = out.join("results.jsonl");
    // Its own process group, as a shell gives a foreground job; Ctrl-C signals the group.
    // A foreground job takes SIGINT's default action, whatever this test inherited (a
    // non-interactive shell starts background jobs with SIGINT ignored, and an ignored
    // signal stays ignored across exec), so the child resets it.
    let mut command = Command::new(env!("CARGO_BIN_EXE_carfollow"));
    // SAFETY: the closure runs in the forked child before exec and calls only `signal`,
    // which is async-signal-safe.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        });
    }
    let mut child = command
        .args([
            "sweep",
            s(&sweep),
            "--out",
            s(&out),
            "--jobs",
            "2",
            "--quiet",
        ])
        .process_group(0)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while std::fs::read_to_string(&results).map_or(0, |t| t.lines().count()) < 2 {
        assert!(std::time::Instant::now() < deadline, "no rows within 120 s");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let group = format!("-{}", child.id());
    assert!(Command::new("kill")
        .args(["-INT", "--", &group])
        .status()
        .unwrap()
        .success());
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "interrupted, it should not report success"
    );
    let kept = std::fs::read_to_string(&results).unwrap();
    let kept_rows = kept.lines().count();
    assert!(
        (2..8).contains(&kept_rows),
        "interrupted midway, yet {kept_rows} rows"
    );
    for line in kept.lines() {
        serde_json::from_str::<Value>(line).expect("every kept row is whole");
    }

    resume_completes(&sweep, &out, &kept, 8);
}

/// `--jobs 0` is refused before any file is written; a merge of a folder without results
/// is an error.
#[test]
fn jobs_0_and_an_empty_merge_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let out = dir.path().join("out");
    let o = carfollow(&["sweep", s(&sweep), "--out", s(&out), "--jobs", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--jobs must be at least 1"));
    assert!(!out.exists(), "a file was written");

    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = carfollow(&["sweep", "merge", s(&empty)]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no sweep results to merge"), "{err}");
    assert!(!empty.join("results.jsonl").exists());
}

/// An output folder that cannot be made (a file stands where it or a parent would be) is an
/// output that cannot be written: exit 3 and one line saying so, from a sweep and from a
/// merge, before any point runs.
#[test]
fn an_output_folder_that_cannot_be_made_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, "").unwrap();
    for out in [blocker.clone(), blocker.join("out")] {
        let o = carfollow(&["sweep", s(&sweep), "--out", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("cannot create the output folder"), "{err}");
        assert!(!err.contains("cannot read results"), "{err}");
    }
    let done = dir.path().join("done");
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&done),
        "--shard",
        "0/2",
    ]));
    let o = carfollow(&["sweep", "merge", s(&done), "--out", s(&blocker.join("m"))]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("cannot create"), "{err}");
}

/// The merge knows the grid (from `sweep.json`): with one shard of two, it lists the
/// other shard's points as missing, says why when a run said so, and exits 3.
#[test]
fn a_merge_of_an_incomplete_sweep_lists_what_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let out = dir.path().join("out");
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--shard",
        "0/2",
    ]));
    let manifest: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    let grid = manifest["points"].as_array().unwrap();
    assert_eq!(grid.len(), 4);
    // Shard 1's first point failed when it ran, as its failed file says.
    let first_of_shard_1 = &grid[1];
    std::fs::write(
        out.join("failed-shard-1-of-2.txt"),
        format!(
            "1\t{}\t{}\tthe renderer failed\n",
            first_of_shard_1["id"].as_str().unwrap(),
            first_of_shard_1["point"].as_str().unwrap()
        ),
    )
    .unwrap();
    let o = carfollow(&["sweep", "merge", s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(
        err.contains("2 of 4 points missing (1 failed, 1 not run)"),
        "{err}"
    );
    let missing = std::fs::read_to_string(out.join("missing.txt")).unwrap();
    let lines: Vec<&str> = missing.lines().collect();
    assert_eq!(lines.len(), 2, "{missing}");
    assert!(lines[0].starts_with("1\t") && lines[0].ends_with("\tfailed: the renderer failed"));
    assert!(lines[1].starts_with("3\t") && lines[1].ends_with("\tnot run"));

    // The other shard completes it: the merge is whole, exits 0 and leaves no missing.txt.
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--shard",
        "1/2",
    ]));
    assert!(!out.join("failed-shard-1-of-2.txt").exists());
    ok(carfollow(&["sweep", "merge", s(&out)]));
    assert!(!out.join("missing.txt").exists());
    assert_eq!(ids(&out.join("results.jsonl")).len(), 4);
}

/// `--resume` refuses results of a changed sweep file or other overrides.
#[test]
fn resume_refuses_a_changed_sweep_or_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let out = dir.path().join("out");
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--shard",
        "0/2",
    ]));
    let changed = carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--resume",
        "--set",
        "environment.sun.strength=0.5",
    ]);
    assert_eq!(changed.status.code(), Some(2));
    let err = String::from_utf8_lossy(&changed.stderr);
    assert!(err.contains("are of another sweep"), "{err}");
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace("[1, 2]", "[1, 3]"),
    )
    .unwrap();
    let changed = carfollow(&["sweep", s(&sweep), "--out", s(&out), "--resume"]);
    assert_eq!(changed.status.code(), Some(2));
    // Nothing was run into the folder.
    assert!(!out.join("results.jsonl").exists());

    // The rows carry the hash too: without sweep.json, a resume of the changed sweep and a
    // merge with another sweep's rows are still refused.
    let shard = out.join("results-shard-0-of-2.jsonl");
    let row: Value = serde_json::from_str(
        std::fs::read_to_string(&shard)
            .unwrap()
            .lines()
            .next()
            .unwrap(),
    )
    .unwrap();
    assert_eq!(row["sweep_hash"].as_str().unwrap().len(), 16, "{row}");
    std::fs::remove_file(out.join("sweep.json")).unwrap();
    let changed = carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&out),
        "--resume",
        "--shard",
        "0/2",
    ]);
    assert_eq!(changed.status.code(), Some(2));
    let err = String::from_utf8_lossy(&changed.stderr);
    assert!(err.contains("its rows are of another sweep"), "{err}");
    let other = dir.path().join("other");
    ok(carfollow(&[
        "sweep",
        s(&sweep),
        "--out",
        s(&other),
        "--shard",
        "1/2",
    ]));
    let o = carfollow(&[
        "sweep",
        "merge",
        s(&out),
        s(&other),
        "--out",
        s(&dir.path().join("m")),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("results of different sweeps"), "{err}");
}

/// Off a terminal, without --quiet, a sweep writes progress lines to stderr.
#[test]
fn progress_lines_off_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_file(dir.path(), TINY);
    let o = Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(["sweep", s(&sweep), "--out", s(&dir.path().join("out"))])
        .args(["--progress-every", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    for n in 1..=4 {
        assert!(
            err.contains(&format!("sweep: {n}/4 points done, 0 could not run")),
            "{err}"
        );
    }
}

/// `--resume` refuses results made with another version of a scenario file the sweep names,
/// or of the target file a scenario reads: old and new results would mix.
#[test]
fn resume_refuses_a_changed_scenario_or_target_file() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    let scenarios = dir.path().join("scenarios");
    std::fs::create_dir_all(scenarios.join("targets")).unwrap();
    let scenario = scenarios.join("weave.toml");
    let target = scenarios.join("targets/nist-ten-segment.toml");
    std::fs::copy(root.join("weave.toml"), &scenario).unwrap();
    std::fs::copy(root.join("targets/nist-ten-segment.toml"), &target).unwrap();
    let sweep = dir.path().join("sweep.toml");
    std::fs::write(
        &sweep,
        TINY.replace("SCENARIOS", &scenarios.display().to_string()),
    )
    .unwrap();
    let out = dir.path().join("out");
    let shard = |extra: &[&str]| {
        let mut args = vec!["sweep", s(&sweep), "--out", s(&out)];
        args.extend(extra);
        carfollow(&args)
    };
    ok(shard(&["--shard", "0/2"]));
    for file in [&target, &scenario] {
        let before = std::fs::read_to_string(file).unwrap();
        std::fs::write(file, format!("{before}\n# edited\n")).unwrap();
        let changed = shard(&["--resume"]);
        assert_eq!(changed.status.code(), Some(2), "{}", file.display());
        let err = String::from_utf8_lossy(&changed.stderr);
        assert!(
            err.contains("are of another sweep") && err.contains("scenario or target file"),
            "{err}"
        );
        std::fs::write(file, before).unwrap();
    }
    // As they were, the resume finishes the sweep.
    ok(shard(&["--resume"]));
}

/// `--dry-run` checks the sweep and plans every point, says how many there are (in the
/// shard too), and runs and writes nothing; a point that cannot be planned fails it with
/// status 2, as it fails a run before anything starts.
#[test]
fn a_dry_run_checks_every_point_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(dir.path(), TINY);
    let out_dir = dir.path().join("out");
    let out = ok(carfollow(&[
        "sweep",
        s(&file),
        "--dry-run",
        "--shard",
        "1/3",
        "--out",
        s(&out_dir),
    ]));
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("valid: 4 points (1 scenario × 2 seeds × 2 combinations of the axes)")
            && said.contains(", 1 in shard 1/3"),
        "{said}"
    );
    assert!(!out_dir.exists(), "a dry run wrote {}", out_dir.display());
    // A value only one point has, which planning refuses (the target out of view at t = 0).
    let bad = sweep_file(
        dir.path(),
        &TINY.replace(
            "[axes]",
            "[axes]\ncamera.mount.pitch_down_deg = [5.0, 40.0]",
        ),
    );
    let out = carfollow(&["sweep", s(&bad), "--dry-run", "--out", s(&out_dir)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("out of the camera's view"), "{err}");
    assert!(!out_dir.exists());
}

/// The Euro NCAP car-to-car rear sweeps as shipped plan every point (checked, not run: the
/// three are 240 runs), each the protocol's grid (CCRs's with its overlaps) in both modes
/// and through both lenses.
#[test]
fn the_ncap_sweeps_plan_every_point() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/sweeps");
    for (file, points) in [
        (
            "ncap-ccr.toml",
            "valid: 180 points (1 scenario × 1 seed × 180 combinations",
        ),
        (
            "ncap-ccrm.toml",
            "valid: 44 points (1 scenario × 1 seed × 44 combinations",
        ),
        (
            "ncap-ccrb.toml",
            "valid: 16 points (1 scenario × 1 seed × 16 combinations",
        ),
    ] {
        let path = root.join(file);
        let out = ok(carfollow(&["sweep", s(&path), "--dry-run"]));
        let said = String::from_utf8_lossy(&out.stdout);
        assert!(said.contains(points), "{file}: {said}");
    }
}
