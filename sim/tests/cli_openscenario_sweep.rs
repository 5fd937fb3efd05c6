//! OpenSCENARIO parameter distributions through the command line: `carfollow sweep
//! FILE.xosc` runs each run of a `ParameterValueDistribution` as a sweep's point (its
//! scenario file with the run's parameter values, as `--param` gives them), with a sweep's
//! results and report; a stochastic distribution draws the same runs every time; what
//! carfollow does not read is refused in one line naming the file and the line. The files
//! are carfollow's own (`sim/core/tests/data/openscenario/cut-in-distribution.xosc`,
//! `cut-in-stochastic.xosc`) and esmini's (MPL-2.0, `esmini/xosc/cut-in_parameter_set.xosc`).
//! Run with `cargo test --release -p sim --test cli_openscenario_sweep`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim/core/tests/data/openscenario")
}

fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The points a dry run lists: the lines after the first, without their ids.
fn listed(o: &Output) -> Vec<String> {
    stdout(o)
        .lines()
        .skip(1)
        .map(|l| l.split_once(' ').unwrap().1.to_string())
        .collect()
}

/// The `$NAME=value` params of a listed point.
fn param<'a>(point: &'a str, name: &str) -> &'a str {
    let key = format!("${name}=");
    point
        .split(' ')
        .find_map(|w| w.strip_prefix(key.as_str()))
        .unwrap_or_else(|| panic!("{point}: no {name}"))
}

#[test]
fn a_deterministic_distribution_is_the_product_of_its_distributions() {
    let file = data().join("cut-in-distribution.xosc");
    let o = carfollow(&["sweep", file.to_str().unwrap(), "--dry-run"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("valid: 6 points (6 runs of"),
        "{}",
        stdout(&o)
    );
    let points = listed(&o);
    let params: Vec<(String, String, String)> = points
        .iter()
        .map(|p| {
            (
                param(p, "LeadSpeed").to_string(),
                param(p, "CutInGap").to_string(),
                param(p, "VanKind").to_string(),
            )
        })
        .collect();
    // The set outermost, the range (10 to 20 by 5, inclusive) inside it, the value set last.
    let expected: Vec<(String, String, String)> = ["40", "55"]
        .iter()
        .flat_map(|s| {
            ["10", "15", "20"]
                .iter()
                .map(move |g| (s.to_string(), g.to_string(), "\"van\"".to_string()))
        })
        .collect();
    assert_eq!(params, expected);
}

#[test]
fn a_distribution_runs_as_a_sweep_each_point_as_its_scenario_with_those_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("cut-in-distribution.xosc");
    let out = dir.path().join("sweep");
    let o = carfollow(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--set",
        "duration_s=2",
        "--jobs",
        "2",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let rows = result_rows(&out);
    assert_eq!(rows.len(), 6);
    for name in ["table.csv", "summary.md", "sweep.json"] {
        assert!(out.join(name).exists(), "no {name}");
    }
    // The numeric parameters are axes of the report.
    assert!(out.join("sweep-$CutInGap.png").exists());
    // A point is its scenario file with its parameters: its figures are `run`'s.
    let row = point_55_15(&rows);
    let run_dir = dir.path().join("run");
    let o = carfollow(&[
        "run",
        data().join("cut-in.xosc").to_str().unwrap(),
        "--param",
        "LeadSpeed=55",
        "--param",
        "CutInGap=15",
        "--param",
        "VanKind=van",
        "--set",
        "duration_s=2",
        "--out",
        run_dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_point_is_run(row, &run_dir);
    // Resumed, nothing is left to run.
    let o = carfollow(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--set",
        "duration_s=2",
        "--resume",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("6 already done, 0 to run"),
        "{}",
        stderr(&o)
    );
}

/// A distribution whose scenario names its chase otherwise than the default names runs
/// with `--ego` naming it, every point as `run --ego` runs it; without, it is refused in
/// one line before anything runs, and `--ego` on a sweep of carfollow's own scenarios is
/// refused too.
#[test]
fn a_distribution_runs_with_the_chase_named_by_ego() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = std::fs::read_to_string(data().join("cut-in.xosc")).unwrap();
    let renamed = scenario
        .replace("name=\"Ego\"", "name=\"Hmmwv\"")
        .replace("entityRef=\"Ego\"", "entityRef=\"Hmmwv\"");
    assert!(!renamed.contains("\"Ego\""));
    std::fs::write(dir.path().join("cut-in.xosc"), renamed).unwrap();
    std::fs::copy(
        data().join("two-lanes.xodr"),
        dir.path().join("two-lanes.xodr"),
    )
    .unwrap();
    std::fs::create_dir(dir.path().join("catalogs")).unwrap();
    for entry in std::fs::read_dir(data().join("catalogs"))
        .unwrap()
        .flatten()
    {
        std::fs::copy(
            entry.path(),
            dir.path().join("catalogs").join(entry.file_name()),
        )
        .unwrap();
    }
    let file = dir.path().join("cut-in-distribution.xosc");
    std::fs::copy(data().join("cut-in-distribution.xosc"), &file).unwrap();
    let file = file.to_str().unwrap();

    let o = carfollow(&["sweep", file, "--dry-run"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("ego"), "{}", stderr(&o));

    let out = dir.path().join("sweep");
    let (out_s, run_dir) = (out.to_str().unwrap(), dir.path().join("run"));
    let set = ["--set", "duration_s=2", "--ego", "Hmmwv"];
    let o = carfollow(
        &[
            &["sweep", file, "--out", out_s, "--jobs", "2", "--quiet"],
            &set[..],
        ]
        .concat(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let rows = result_rows(&out);
    assert_eq!(rows.len(), 6);
    let row = point_55_15(&rows);
    let scenario = dir.path().join("cut-in.xosc");
    let params = [
        "--param",
        "LeadSpeed=55",
        "--param",
        "CutInGap=15",
        "--param",
        "VanKind=van",
    ];
    let run_args = [
        scenario.to_str().unwrap(),
        "--out",
        run_dir.to_str().unwrap(),
    ];
    let o = carfollow(&[&["run"][..], &run_args, &params, &set].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_point_is_run(row, &run_dir);

    let own = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/sweeps/smoke.toml");
    let o = carfollow(&[
        "sweep",
        own.to_str().unwrap(),
        "--dry-run",
        "--ego",
        "Hmmwv",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("lists no OpenSCENARIO scenario"),
        "{}",
        stderr(&o)
    );
}

/// The rows of a sweep's `results.jsonl` in `out`.
fn result_rows(out: &Path) -> Vec<serde_json::Value> {
    let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    results
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// The point of `cut-in-distribution.xosc` with LeadSpeed 55 and CutInGap 15.
fn point_55_15(rows: &[serde_json::Value]) -> &serde_json::Value {
    rows.iter()
        .find(|r| r["params"]["$LeadSpeed"] == 55 && r["params"]["$CutInGap"] == 15)
        .expect("the point LeadSpeed 55, CutInGap 15")
}

/// A sweep's result `row` has the figures of the run written to `run_dir`.
fn assert_point_is_run(row: &serde_json::Value, run_dir: &Path) {
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(find(run_dir, "summary.json")).unwrap())
            .unwrap();
    for pointer in ["/frames", "/range_error_m", "/tracking_lost_s", "/traffic"] {
        assert_eq!(
            row["summary"].pointer(pointer),
            summary.pointer(pointer),
            "{pointer}"
        );
    }
}

/// The file `name` somewhere under `dir`.
fn find(dir: &Path, name: &str) -> PathBuf {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let p = entry.path();
        if p.file_name().is_some_and(|n| n == name) {
            return p;
        }
        if p.is_dir() {
            let found = find(&p, name);
            if found.exists() {
                return found;
            }
        }
    }
    dir.join("missing").join(name)
}

#[test]
fn a_stochastic_distribution_draws_the_same_runs_every_time_within_its_ranges() {
    let file = data().join("cut-in-stochastic.xosc");
    let first = carfollow(&["sweep", file.to_str().unwrap(), "--dry-run"]);
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    assert!(
        stdout(&first).contains("5 runs of") && stdout(&first).contains("randomSeed 42"),
        "{}",
        stdout(&first)
    );
    let again = carfollow(&["sweep", file.to_str().unwrap(), "--dry-run"]);
    assert_eq!(listed(&first), listed(&again));
    let points = listed(&first);
    assert_eq!(points.len(), 5);
    let speeds: Vec<f64> = points
        .iter()
        .map(|p| param(p, "LeadSpeed").parse().unwrap())
        .collect();
    assert!(
        speeds.iter().all(|s| (40.0..=60.0).contains(s)),
        "{speeds:?}"
    );
    assert!(speeds.windows(2).any(|w| w[0] != w[1]), "{speeds:?}");
    for p in &points {
        let gap: f64 = param(p, "CutInGap").parse().unwrap();
        assert!((8.0..=20.0).contains(&gap), "{p}");
        assert_eq!(param(p, "VanKind"), "\"van\"");
    }
    // Another seed, other draws.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("randomSeed=\"42\"", "randomSeed=\"43\"");
    let other = write_beside(&dir, "other.xosc", &text);
    let o = carfollow(&["sweep", other.to_str().unwrap(), "--dry-run"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_ne!(listed(&o), points);
}

/// `text` as `name` in `dir`, beside a copy of the cut-in's files.
fn write_beside(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    for f in [
        "cut-in.xosc",
        "two-lanes.xodr",
        "catalogs/VehicleCatalog.xosc",
    ] {
        let to = dir.path().join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(data().join(f), to).unwrap();
    }
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn what_carfollow_does_not_read_is_refused_at_its_line() {
    let text = std::fs::read_to_string(data().join("cut-in-stochastic.xosc")).unwrap();
    let deterministic = std::fs::read_to_string(data().join("cut-in-distribution.xosc")).unwrap();
    let cases: Vec<(String, &str)> = vec![
        (
            text.replace(
                "<Histogram>",
                "<UserDefinedDistribution type=\"mine\">x</UserDefinedDistribution><Histogram>",
            ),
            "more than one element",
        ),
        (
            text.replace(
                "<ProbabilityDistributionSet>\n          <Element value=\"van\" weight=\"1\"/>\n        </ProbabilityDistributionSet>",
                "<UserDefinedDistribution type=\"mine\">x</UserDefinedDistribution>",
            ),
            "unsupported distribution <UserDefinedDistribution>",
        ),
        (
            text.replace("weight=\"1\"/>", "weight=\"0\"/>"),
            "weights sum to more than 0",
        ),
        (
            text.replace("parameterName=\"CutInGap\"", "parameterName=\"Nope\""),
            "declares no parameter `Nope`",
        ),
        (
            text.replace("revMinor=\"3\"", "revMinor=\"0\""),
            "parameter distributions are OpenSCENARIO 1.1 to 1.3",
        ),
        (
            text.replace("lowerLimit=\"40\" upperLimit=\"60\"", "lowerLimit=\"60\" upperLimit=\"40\""),
            "needs lowerLimit <= upperLimit",
        ),
        (
            text.replace("lowerLimit=\"40\" upperLimit=\"60\"", "lowerLimit=\"400\" upperLimit=\"600\""),
            "holds too little of it",
        ),
        (
            text.replace("numberOfTestRuns=\"5\"", "numberOfTestRuns=\"0\""),
            "numberOfTestRuns",
        ),
        (
            deterministic.replace(
                "<DistributionRange stepWidth=\"5\">\n          <Range lowerLimit=\"10\" upperLimit=\"20\"/>\n        </DistributionRange>",
                "<UserDefinedDistribution type=\"mine\">x</UserDefinedDistribution>",
            ),
            "unsupported distribution <UserDefinedDistribution>",
        ),
        (
            deterministic.replace("stepWidth=\"5\"", "stepWidth=\"0.0001\""),
            "at most 10000",
        ),
        (
            deterministic.replace("parameterRef=\"VanKind\"", "parameterRef=\"LeadSpeed\""),
            "set by another distribution too",
        ),
        (
            deterministic.replace("filepath=\"cut-in.xosc\"", "filepath=\"none.xosc\""),
            "none.xosc",
        ),
    ];
    for (i, (mutant, says)) in cases.iter().enumerate() {
        assert_ne!(mutant, &text, "case {i} changed nothing");
        let dir = tempfile::tempdir().unwrap();
        let path = write_beside(&dir, "mutant.xosc", mutant);
        let out = dir.path().join("out");
        let o = carfollow(&[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "case {i}: {e}");
        assert_eq!(e.lines().count(), 1, "case {i}: {e}");
        assert!(
            e.contains("mutant.xosc:") && e.contains(says),
            "case {i}: {e}"
        );
        assert!(!out.exists(), "case {i}: a refused sweep wrote something");
    }
    // A distribution is not a scenario, and a scenario not a distribution.
    let file = data().join("cut-in-distribution.xosc");
    let o = carfollow(&["check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("carfollow sweep"), "{}", stderr(&o));
    let o = carfollow(&[
        "sweep",
        data().join("cut-in.xosc").to_str().unwrap(),
        "--dry-run",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("not a parameter distribution"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn esminis_distribution_expands_into_twelve_runs_without_a_lead() {
    // esmini's cut-in over two sets of vehicles, two speeds and three speed factors: its
    // scenario has no vehicle ahead of the ego in its lane (the one that cuts in starts in
    // the next lane), so the chase follows none and cruises until it finds one; every
    // point plans, the fastest overtaker (1.5 × 110 km/h) starting at carfollow's top speed.
    let file = data().join("esmini/xosc/cut-in_parameter_set.xosc");
    let o = carfollow(&["sweep", file.to_str().unwrap(), "--dry-run"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{e}");
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(out.contains("valid: 12 points"), "{out}");
    assert_eq!(out.matches("cut-in seed=0").count(), 12, "{out}");
}

/// `--resume` takes a folder's rows only while nothing the points read has changed: with a
/// catalog entry or the road file changed since, it says the rows are of another sweep and
/// runs nothing; changed back, it resumes.
#[test]
fn a_resume_after_a_catalog_or_road_file_changed_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(data().join("cut-in-distribution.xosc")).unwrap();
    let file = write_beside(&dir, "dist.xosc", &text);
    let out = dir.path().join("sweep");
    let sweep = |resume: bool| {
        let mut args = vec![
            "sweep",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--set",
            "duration_s=1",
        ];
        if resume {
            args.push("--resume");
        }
        carfollow(&args)
    };
    let o = sweep(false);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let resumes = || {
        let o = sweep(true);
        o.status.code() == Some(0) && stderr(&o).contains("6 already done, 0 to run")
    };
    assert!(resumes());
    for (name, from, to) in [
        (
            "catalogs/VehicleCatalog.xosc",
            "<Vehicle name=\"van\" vehicleCategory=\"van\">",
            "<Vehicle name=\"van\" vehicleCategory=\"truck\">",
        ),
        ("two-lanes.xodr", "a=\"3.5\"", "a=\"3.6\""),
    ] {
        let path = dir.path().join(name);
        let original = std::fs::read_to_string(&path).unwrap();
        assert!(original.contains(from), "{name}");
        std::fs::write(&path, original.replace(from, to)).unwrap();
        let o = sweep(true);
        assert_ne!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("of another sweep") && stderr(&o).lines().count() == 1,
            "{name}: {}",
            stderr(&o)
        );
        std::fs::write(&path, original).unwrap();
        assert!(resumes(), "{name} changed back");
    }
}
