//! The cluster examples run as written, on a tiny sweep: `examples/slurm/sweep.sbatch` as
//! every task of its job array (with a stand-in `sbatch` that runs the merge job it
//! queues), and the command of `examples/kubernetes/sweep-job.yaml` as every pod of the
//! Indexed Job, then `merge-job.yaml`'s. Each ends with every point of the sweep exactly
//! once. Run with `cargo test --release -p sim --test cluster_examples`.
#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Two λ values × two seeds on `weave`, 1 s each: four points.
fn tiny_sweep(dir: &Path) -> PathBuf {
    let scenarios = repo().join("scenarios");
    let path = dir.join("tiny.toml");
    std::fs::write(
        &path,
        format!(
            "scenarios = [\"{}/weave.toml\"]\nseeds = [1, 2]\nset = [\"duration_s=1.0\"]\n[axes]\ntracker.lambda = [0.6, 0.9]\n",
            scenarios.display()
        ),
    )
    .unwrap();
    path
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A folder for PATH holding `carfollow` (the binary under test) and the given scripts.
fn bin_dir(dir: &Path, scripts: &[(&str, &str)]) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_carfollow"), bin.join("carfollow")).unwrap();
    for (name, text) in scripts {
        let path = bin.join(name);
        std::fs::write(&path, text).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    bin
}

fn path_with(bin: &Path) -> String {
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

/// The merged results: every point once, in grid order, with the report beside them.
fn check_merged(out: &Path) {
    let text = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let indices: Vec<u64> = text
        .lines()
        .map(|l| {
            serde_json::from_str::<serde_json::Value>(l).unwrap()["index"]
                .as_u64()
                .unwrap()
        })
        .collect();
    assert_eq!(indices, vec![0, 1, 2, 3], "{text}");
    for f in ["table.csv", "summary.md", "sweep-tracker.lambda.png"] {
        assert!(out.join(f).exists(), "{f}");
    }
}

#[test]
fn the_slurm_job_array_runs_every_shard_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = tiny_sweep(dir.path());
    let out = dir.path().join("out");
    let log = dir.path().join("sbatch.log");
    // Slurm's sbatch, standing in: records its arguments and runs the --wrap command now
    // (the array's last task is run last here, so its dependency has been met).
    let sbatch = format!(
        "#!/bin/sh\necho \"$@\" >> '{}'\nfor a in \"$@\"; do case \"$a\" in --wrap=*) sh -c \"${{a#--wrap=}}\" || exit 1;; esac; done\n",
        log.display()
    );
    let bin = bin_dir(dir.path(), &[("sbatch", &sbatch)]);
    let n = 3;
    for task in 0..n {
        let status = Command::new("bash")
            .arg(repo().join("examples/slurm/sweep.sbatch"))
            .current_dir(repo())
            .env("PATH", path_with(&bin))
            .env("SWEEP", &sweep)
            .env("N", n.to_string())
            .env("OUT", &out)
            .env("CARFOLLOW", bin.join("carfollow"))
            .env("SLURM_ARRAY_TASK_ID", task.to_string())
            .env("SLURM_ARRAY_JOB_ID", "4242")
            .env("SLURM_CPUS_PER_TASK", "1")
            .status()
            .unwrap();
        assert!(status.success(), "task {task}");
        assert!(out
            .join(format!("results-shard-{task}-of-{n}.jsonl"))
            .exists());
    }
    let queued = std::fs::read_to_string(&log).unwrap();
    assert_eq!(queued.lines().count(), 1, "one merge job: {queued}");
    assert!(queued.contains("--dependency=afterany:4242"), "{queued}");
    check_merged(&out);
}

/// The lines of the folded block (`- >-`) under `args:` in a Job manifest, joined.
fn folded_command(yaml: &str) -> String {
    let lines: Vec<&str> = yaml.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim() == "- >-")
        .expect("a `- >-` block");
    let indent = |l: &str| l.len() - l.trim_start().len();
    let body = indent(lines[start + 1]);
    lines[start + 1..]
        .iter()
        .take_while(|l| indent(l) >= body && !l.trim().is_empty())
        .map(|l| l.trim())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The value of `key: value` (first occurrence), unquoted.
fn yaml_value<'a>(yaml: &'a str, key: &str) -> &'a str {
    let line = yaml
        .lines()
        .find(|l| l.trim_start().starts_with(&format!("{key}:")))
        .unwrap_or_else(|| panic!("no {key}"));
    line.split_once(':').unwrap().1.trim().trim_matches('"')
}

#[test]
fn the_kubernetes_indexed_job_runs_every_shard_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = tiny_sweep(dir.path());
    let volume = dir.path().join("sweeps");
    let bin = bin_dir(dir.path(), &[]);
    let examples = repo().join("examples/kubernetes");
    let job = std::fs::read_to_string(examples.join("sweep-job.yaml")).unwrap();
    let completions: usize = yaml_value(&job, "completions").parse().unwrap();
    let shards = {
        let at = job.find("name: SHARDS").expect("a SHARDS variable");
        yaml_value(&job[at..], "value")
    };
    assert_eq!(
        shards,
        completions.to_string(),
        "SHARDS must equal completions"
    );
    // Each pod: the container's command with the volume at `volume` and the tiny sweep
    // (more shards than points: some pods have nothing to do, and must still succeed).
    let command = folded_command(&job).replace("/sweeps", volume.to_str().unwrap());
    for index in 0..completions {
        let status = Command::new("sh")
            .arg("-c")
            .arg(&command)
            .current_dir(repo())
            .env("PATH", path_with(&bin))
            .env("SWEEP", &sweep)
            .env("SHARDS", shards)
            .env("JOB_COMPLETION_INDEX", index.to_string())
            .status()
            .unwrap();
        assert!(status.success(), "pod {index}: {command}");
    }
    // The merge Job's arguments, as the image's entrypoint (carfollow) gets them.
    let merge = std::fs::read_to_string(examples.join("merge-job.yaml")).unwrap();
    let args: Vec<String> = serde_json::from_str(yaml_value(&merge, "args")).unwrap();
    let args: Vec<String> = args
        .iter()
        .map(|a| a.replace("/sweeps", volume.to_str().unwrap()))
        .collect();
    let status = Command::new(bin.join("carfollow"))
        .args(&args)
        .status()
        .unwrap();
    assert!(status.success(), "merge: {args:?}");
    check_merged(&volume.join("lambda"));
}

/// A last array task whose own sweep fails (exit status 3: a point could not run) still
/// queues the merge, and fails with that status itself.
#[test]
fn a_failing_last_slurm_task_still_queues_the_merge() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = tiny_sweep(dir.path());
    let out = dir.path().join("out");
    let log = dir.path().join("sbatch.log");
    let sbatch = format!("#!/bin/sh\necho \"$@\" >> '{}'\n", log.display());
    // carfollow, standing in: runs the real sweep, then reports a point that could not run.
    let failing = format!(
        "#!/bin/sh\n'{}' \"$@\"\nexit 3\n",
        env!("CARGO_BIN_EXE_carfollow")
    );
    let bin = bin_dir(dir.path(), &[("sbatch", &sbatch), ("failing", &failing)]);
    let status = Command::new("bash")
        .arg(repo().join("examples/slurm/sweep.sbatch"))
        .current_dir(repo())
        .env("PATH", path_with(&bin))
        .env("SWEEP", &sweep)
        .env("N", "1")
        .env("OUT", &out)
        .env("CARFOLLOW", bin.join("failing"))
        .env("SLURM_ARRAY_TASK_ID", "0")
        .env("SLURM_ARRAY_JOB_ID", "4243")
        .env("SLURM_CPUS_PER_TASK", "1")
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(3));
    let queued = std::fs::read_to_string(&log).unwrap();
    assert_eq!(queued.lines().count(), 1, "one merge job: {queued}");
    assert!(queued.contains("--dependency=afterany:4243"), "{queued}");
}
