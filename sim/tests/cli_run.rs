//! `carfollow run` end to end: two renderers (the second in a worker process) give the same
//! outputs as one; rendering only the part of each frame the tracker reads gives the
//! estimates of whole frames (`--video` and `--mcap` render whole frames); the exit status follows the `[expect]` verdict; bad input exits 2 with a
//! one-line error. Run with `cargo test --release -p sim --test cli_run`.

use std::path::Path;
use std::process::{Command, Output};

fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .output()
        .unwrap()
}

fn run(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "run",
        "--quiet",
        "--set",
        "duration_s=4",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    carfollow(&args)
}

/// With two renderers the physics runs a frame further ahead of the records than with one,
/// and the automatic gain control meters each frame before a later one is captured: the
/// records (with the controller's desired gap and mode) and the gains are those of one
/// renderer, with an interlaced camera too.
#[test]
fn two_renderers_keep_the_automatic_gain_and_controller_records_of_one() {
    let dir = tempfile::tempdir().unwrap();
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    let settings = [
        "--set",
        "environment.sensor.auto_gain={target_grey=110,time_constant_s=0.4}",
        "--set",
        "environment.sensor.interlaced=true",
    ];
    for (out, renderers) in [(&one, "1"), (&two, "2")] {
        let mut args = vec!["--renderers", renderers];
        args.extend(settings);
        let status = run(out, &args);
        assert!(
            status.status.code() == Some(0) || status.status.code() == Some(1),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
    }
    let csv = |d: &Path| std::fs::read_to_string(d.join("frames.csv")).unwrap();
    assert!(csv(&one).lines().count() > 50);
    assert!(
        csv(&one) == csv(&two),
        "frames.csv differs between one and two renderers"
    );
}

#[test]
fn two_renderers_give_the_outputs_of_one() {
    let dir = tempfile::tempdir().unwrap();
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    let a = run(&one, &["--renderers", "1"]);
    let b = run(&two, &["--renderers", "2"]);
    for out in [&a, &b] {
        assert!(
            out.status.code() == Some(0) || out.status.code() == Some(1),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stderr.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(a.status.code(), b.status.code());
    let csv = |d: &Path| std::fs::read(d.join("frames.csv")).unwrap();
    assert_eq!(csv(&one).len(), csv(&two).len());
    assert!(
        csv(&one) == csv(&two),
        "frames.csv differs between one and two renderers"
    );

    // The verdict in summary.json matches the exit status, and the timing is reported.
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(two.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["passed"].as_bool(),
        Some(b.status.code() == Some(0))
    );
    assert_eq!(summary["frames"], 60);
    assert_eq!(summary["timing"]["frames"], 60);
    assert_eq!(summary["timing"]["pipelined"], true);
    assert_eq!(summary["timing"]["frames_in_flight"], 2);
    let one: serde_json::Value =
        serde_json::from_slice(&std::fs::read(one.join("summary.json")).unwrap()).unwrap();
    assert_eq!(one["timing"]["frames_in_flight"], 1);
    assert!(summary["timing"]["render_s"].as_f64().unwrap() > 0.0);
}

/// A frame rendered in part whose tracking reads beyond it is rendered whole again, by
/// whichever renderer is free: with two, sometimes the worker. The estimates are those of
/// one renderer all the same. The fixed camera loses the lead in the turns and robust mode
/// searches the whole frame for it.
#[test]
fn frames_rendered_again_in_the_worker_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let turns = scenario("intersections.toml");
    let mut csvs = Vec::new();
    for renderers in ["1", "2"] {
        let out = dir.path().join(renderers);
        let o = run(
            &out,
            &[
                turns.as_str(),
                "--renderers",
                renderers,
                "--set",
                "duration_s=40",
                "--set",
                "camera.pan.enabled=false",
                "--set",
                "tracker.mode=robust",
            ],
        );
        assert_eq!(
            o.status.code(),
            Some(1),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
        assert!(
            summary["timing"]["rerendered_frames"].as_u64().unwrap() >= 1,
            "no frame was rendered again: {}",
            summary["timing"]
        );
        csvs.push(std::fs::read(out.join("frames.csv")).unwrap());
    }
    assert!(
        csvs[0] == csvs[1],
        "frames.csv differs between one and two renderers"
    );
}

#[test]
fn frames_csv_is_the_same_with_and_without_whole_frames() {
    let dir = tempfile::tempdir().unwrap();
    // Robust mode on the bumpy road: the camera pitches, and the tracker searches.
    let gravel = scenario("gravel-road.toml");
    let runs: [(&str, Vec<&str>); 5] = [
        ("part", vec![]),
        ("video", vec!["--video", "--video-stride", "15"]),
        ("mcap", vec!["--mcap"]),
        ("part-one-renderer", vec!["--renderers", "1"]),
        (
            "video-one-renderer",
            vec!["--renderers", "1", "--video", "--video-stride", "15"],
        ),
    ];
    let mut csvs = Vec::new();
    for (name, extra) in &runs {
        let out = dir.path().join(name);
        let mut args = vec![gravel.as_str()];
        args.extend(extra);
        let o = run(&out, &args);
        assert!(
            o.status.code() == Some(0) || o.status.code() == Some(1),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
        assert!(summary["timing"]["rerendered_frames"].as_u64().is_some());
        csvs.push((name, std::fs::read(out.join("frames.csv")).unwrap()));
    }
    let (_, first) = &csvs[0];
    for (name, csv) in &csvs[1..] {
        assert!(
            csv == first,
            "frames.csv of `{name}` differs from the partial frames'"
        );
    }
}

#[test]
fn bad_arguments_exit_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for (extra, needle) in [
        (&["--renderers", "3"][..], "--renderers"),
        (&["--set", "tracker.lamda=0.7"][..], "tracker.lamda"),
        (&["no-such-scenario.toml"][..], "no-such-scenario.toml"),
        // Two scenarios of one name would write to one folder.
        (
            &[
                &scenario("nist-grounds.toml")[..],
                &scenario("nist-grounds.toml"),
            ][..],
            "are both named `nist-grounds`",
        ),
    ] {
        let out = run(dir.path(), extra);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{extra:?}: {err}");
    }
}

/// `check` without files checks what `run` without files runs, the built-in scenario with
/// its overrides: it accepts what `run` runs and refuses, with the same one line and exit
/// status, what `run` refuses.
#[test]
fn check_without_files_checks_the_built_in_scenario() {
    let out = carfollow(&["check"]);
    assert_eq!(out.status.code(), Some(0));
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("ok: `nist-grounds`"), "{said}");
    let dir = tempfile::tempdir().unwrap();
    let bad = "camera.focal_length_mm=200";
    let checked = carfollow(&["check", "--set", bad]);
    let ran = run(dir.path(), &["--set", bad]);
    for out in [&checked, &ran] {
        assert_eq!(out.status.code(), Some(2));
    }
    let err = String::from_utf8_lossy(&checked.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("out of the camera's view"), "{err}");
    assert_eq!(err, String::from_utf8_lossy(&ran.stderr));
}

/// A run in a folder where an earlier run recorded leaves no recording, video or stills of
/// that run behind.
#[test]
fn an_earlier_runs_recording_and_video_do_not_survive_a_run() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["run.mcap", "video.gif", "still_last.png"] {
        std::fs::write(dir.path().join(name), b"old").unwrap();
    }
    let out = run(dir.path(), &["--renderers", "1", "--set", "duration_s=1"]);
    // Completed (a second is too short for every criterion to pass).
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in ["run.mcap", "video.gif", "still_last.png"] {
        assert!(!dir.path().join(name).exists(), "{name}");
    }
    assert!(dir.path().join("frames.csv").exists());
}

fn scenario(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(name)
        .display()
        .to_string()
}

/// Checks `xml` against the common JUnit schema in `tests/data/junit.xsd` with xmllint
/// (`.ci/install` installs it); a machine without it fails here rather than skip.
fn assert_valid_junit(xml: &Path) {
    let xsd = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/junit.xsd");
    let out = Command::new("xmllint")
        .arg("--noout")
        .arg("--schema")
        .arg(&xsd)
        .arg(xml)
        .output()
        .expect("xmllint (libxml2-utils) is needed: run `bash .ci/install`");
    assert!(
        out.status.success(),
        "{} does not validate against the JUnit schema:\n{}",
        xml.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_schema_check_can_fail() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.xml");
    std::fs::write(
        &bad,
        "<testsuites><testsuite name=\"x\" tests=\"1\" failures=\"0\" errors=\"0\" time=\"1\">\
         <testcase name=\"c\" classname=\"k\" time=\"0\"/></testsuite></testsuites>",
    )
    .unwrap();
    // No timestamp: refused.
    let r = std::panic::catch_unwind(|| assert_valid_junit(&bad));
    assert!(r.is_err());
}

/// Several scenarios: a failing criterion does not stop the next scenario, nor does a
/// scenario that cannot complete (its output folder is a file); one combined junit.xml
/// holds them all, valid against the JUnit schema; the exit status is 3, then 1.
#[test]
fn a_multi_scenario_run_goes_on_and_writes_one_junit() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let (weave, close) = (scenario("weave.toml"), scenario("close-range.toml"));
    let root_s = root.to_str().unwrap().to_string();
    let args: Vec<String> = [
        "run",
        "--quiet",
        "--renderers",
        "1",
        "--set",
        "duration_s=1",
        "--set",
        "expect.min_distance_m=100000",
        "--out",
        &root_s,
        &weave,
        &close,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = carfollow(&args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("weave: FAIL") && stdout.contains("close-range: FAIL"),
        "{stdout}"
    );
    let junit = root.join("junit.xml");
    assert_valid_junit(&junit);
    assert_valid_junit(&root.join("weave/junit.xml"));
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert_eq!(xml.matches("<testsuite ").count(), 2, "{xml}");
    assert!(xml.contains("name=\"min_distance\""), "{xml}");
    assert!(
        xml.contains("<failure message=\"measured ") && xml.contains("type=\"expect\">"),
        "{xml}"
    );
    assert!(xml.contains(", limit 100000.000\""), "{xml}");

    // The first scenario cannot write its outputs: it is an <error>, the second still runs.
    std::fs::remove_dir_all(root.join("weave")).unwrap();
    std::fs::write(root.join("weave"), "in the way").unwrap();
    let out = carfollow(&args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert_eq!(
        err.matches("error: weave: could not complete").count(),
        1,
        "{err}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("close-range: FAIL"));
    assert_valid_junit(&junit);
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert!(
        xml.contains("<error ") && xml.contains("type=\"incomplete\""),
        "{xml}"
    );
    assert!(xml.contains("errors=\"1\""), "{xml}");
}

/// summary.json says what ran: versions, the overrides and the resolved scenario.
#[test]
fn summary_json_records_versions_overrides_and_the_resolved_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        dir.path(),
        &["--renderers", "1", "--set", "tracker.lambda=0.7"],
    );
    assert!(matches!(out.status.code(), Some(0 | 1)), "{out:?}");
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["schema_version"], 4);
    assert!(s["partly_out_of_view_s"].is_number(), "{s}");
    assert_eq!(s["carfollow_version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(
        s["overrides"],
        serde_json::json!(["duration_s=4", "tracker.lambda=0.7"])
    );
    assert_eq!(s["resolved_scenario"]["tracker"]["lambda"], 0.7);
    assert_eq!(s["resolved_scenario"]["duration_s"], 4.0);
    assert_eq!(s["resolved_scenario"]["name"], "nist-grounds");
    // The defaults the file left out, as the run used them; the controller's camera as the
    // camera was mounted; f32 fields as written (2.2, not 2.200000047683716).
    let r = &s["resolved_scenario"];
    assert_eq!(r["environment"]["clutter"]["parked_vehicles_per_km"], 6.0);
    assert_eq!(r["environment"]["textures"]["enabled"], true);
    assert_eq!(
        r["chase"]["controller"]["camera_mount"],
        r["camera"]["mount"]
    );
    assert_eq!(r["camera"]["mount"]["forward_m"], 2.2);
    assert!(r["chase"]["controller"]["half_fov_deg"].as_f64().unwrap() > 21.0);
    // The tracker's, the loop's and the sensor's defaults too.
    assert_eq!(r["tracker"]["mode"], "paper");
    assert_eq!(r["tracker"]["delta_deg"], 15.0);
    assert_eq!(r["loop"]["rate_hz"], 15.0);
    assert_eq!(r["loop"]["latency_ms"], 128.0);
    assert!(r["environment"]["sensor"]["noise_sigma_grey"].is_number());
    // Every field is filled but the optional parts that are off: the sensor's effects, a
    // chase speed profile (the gap keeper drives) and the bumps (a flat road).
    let mut nulls = Vec::new();
    fn walk(v: &serde_json::Value, at: &str, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Null => out.push(at.to_string()),
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    walk(x, &format!("{at}.{k}"), out);
                }
            }
            _ => {}
        }
    }
    walk(r, "", &mut nulls);
    let effects = [
        ".environment.sensor.blur_sigma_px",
        ".environment.sensor.shot_noise_full_well_e",
        ".environment.sensor.auto_gain",
        ".chase.speed_profile",
        ".environment.bumps",
    ];
    nulls.retain(|n| !effects.contains(&n.as_str()));
    assert!(nulls.is_empty(), "left null: {nulls:?}");
    if let Some(commit) = s.get("git_commit") {
        assert_eq!(commit.as_str().unwrap().len(), 40, "{commit}");
    }
}

/// Off a terminal, progress goes to stderr as lines (the bar would stay hidden).
#[test]
fn progress_lines_off_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let out = carfollow(&[
        "run",
        "--renderers",
        "1",
        "--set",
        "duration_s=1",
        "--progress-every",
        "0",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(matches!(out.status.code(), Some(0 | 1)), "{err}");
    let lines = err
        .lines()
        .filter(|l| l.starts_with("nist-grounds: t "))
        .count();
    assert!(lines >= 10, "{err}");
    assert!(err.contains("× real time, gap "), "{err}");
}

/// An error is said once: the OS error of a missing file, a target file's error.
#[test]
fn errors_are_said_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = carfollow(&["run", "--quiet", "no-such-scenario.toml"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(err.matches("os error 2").count(), 1, "{err}");

    // A scenario whose target file has a corner 1e308 m out.
    let targets = dir.path().join("targets");
    std::fs::create_dir(&targets).unwrap();
    let target = std::fs::read_to_string(scenario("targets/nist-ten-segment.toml")).unwrap();
    std::fs::write(
        targets.join("nist-ten-segment.toml"),
        target.replacen("[-0.8, 0.5]", "[-1e308, 0.5]", 1),
    )
    .unwrap();
    let file = dir.path().join("s.toml");
    std::fs::copy(scenario("weave.toml"), &file).unwrap();
    for args in [
        vec!["run", "--quiet", file.to_str().unwrap()],
        vec!["check", file.to_str().unwrap()],
    ] {
        let out = carfollow(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(
            err.matches("corner 0 = [-1e308, 0.5]").count(),
            1,
            "{args:?}: {err}"
        );
    }
    let out = carfollow(&[
        "target",
        targets.join("nist-ten-segment.toml").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
}

/// `--help` documents the exit statuses.
#[test]
fn help_documents_exit_statuses() {
    for args in [&["--help"][..], &["run", "--help"][..]] {
        let out = carfollow(args);
        let text = String::from_utf8_lossy(&out.stdout).replace('\n', " ");
        let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            text.contains("3 when a run could not complete"),
            "{args:?}: {text}"
        );
    }
    // A sweep's failed criteria are its results: it exits 0 when every point ran.
    let out = carfollow(&["sweep", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(text.contains("0 when every point ran"), "{text}");
}

/// A bad argument of `target` is refused before the target is listed: one line, nothing
/// else said.
#[test]
fn target_refuses_a_bad_width_before_saying_anything() {
    let dir = tempfile::tempdir().unwrap();
    let out = carfollow(&[
        "target",
        &scenario("targets/nist-ten-segment.toml"),
        "--width",
        "0",
        "--out",
        dir.path().join("t.png").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("--width"), "{err}");
}

/// `render` and `target` write PNGs: another format is bad input, refused before anything
/// is drawn or said, with exit status 2 and one line.
#[test]
fn image_outputs_that_are_not_png_are_refused_before_anything_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let target = scenario("targets/nist-ten-segment.toml");
    for name in ["f.jpg", "f"] {
        let path = dir.path().join(name);
        let path = path.to_str().unwrap();
        for args in [
            vec!["render", "--out", path],
            vec!["target", &target, "--out", path],
        ] {
            let out = carfollow(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
            assert!(out.stdout.is_empty(), "{args:?}");
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(err.contains("ending in .png"), "{err}");
            assert!(!dir.path().join(name).exists());
        }
    }
}

/// An output that cannot be written is a run that could not complete: exit status 3.
#[test]
fn an_unwritable_output_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, "").unwrap();
    let png = blocker.join("target.png");
    let out = carfollow(&[
        "target",
        &scenario("targets/nist-ten-segment.toml"),
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(3));
    // A single run whose output folder is a file.
    let out = run(&blocker, &["--renderers", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

/// `--video-stride N` puts every N-th frame into video.gif.
#[test]
fn video_stride_thins_the_gif() {
    let dir = tempfile::tempdir().unwrap();
    for (stride, frames) in [("5", 3), ("1", 15)] {
        let out_dir = dir.path().join(stride);
        let out = run(
            &out_dir,
            &[
                "--renderers",
                "1",
                "--set",
                "duration_s=1",
                "--video",
                "--video-stride",
                stride,
            ],
        );
        assert!(matches!(out.status.code(), Some(0 | 1)), "{out:?}");
        let gif = std::fs::File::open(out_dir.join("video.gif")).unwrap();
        let mut decoder = gif::DecodeOptions::new().read_info(gif).unwrap();
        let mut n = 0;
        while decoder.read_next_frame().unwrap().is_some() {
            n += 1;
        }
        assert_eq!(n, frames, "--video-stride {stride}");
    }
}

/// With the camera on a pan head, turning through `intersections`' first right-angle turn,
/// the render worker draws what this process would: the head's angle crosses to it bit for
/// bit, and `frames.csv` records it.
#[test]
fn a_panned_camera_renders_alike_in_the_worker() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/intersections.toml");
    let runs: Vec<std::path::PathBuf> = ["1", "2"]
        .iter()
        .map(|n| {
            let out = dir.path().join(n);
            let o = carfollow(&[
                "run",
                scenario.to_str().unwrap(),
                "--quiet",
                "--set",
                "duration_s=14",
                "--renderers",
                n,
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(
                matches!(o.status.code(), Some(0 | 1)),
                "{}",
                String::from_utf8_lossy(&o.stderr)
            );
            out
        })
        .collect();
    let csv = |d: &Path| std::fs::read_to_string(d.join("frames.csv")).unwrap();
    assert!(csv(&runs[0]) == csv(&runs[1]), "frames.csv differs");
    let text = csv(&runs[0]);
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|c| *c == "camera_pan_deg").unwrap();
    let most = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(col).unwrap().parse::<f64>().unwrap().abs())
        .fold(0.0, f64::max);
    assert!(most > 10.0, "the head turned only {most}°");
}

/// A reader that leaves early (`carfollow run | head -1`) costs nothing: no panic, the run's
/// own exit status, and every output written.
#[test]
fn a_closed_stdout_is_no_failure() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args([
            "run",
            "--set",
            "duration_s=2",
            "--out",
            dir.path().to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Close the reading end before the run says anything.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(matches!(out.status.code(), Some(0 | 1)), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(dir.path().join("summary.json").is_file());
}

/// A `--set` that cannot apply is the command's error, said once, not a count of invalid
/// files; files that are invalid are counted, with the noun agreeing.
#[test]
fn check_says_a_bad_set_once_and_counts_bad_files() {
    let out = carfollow(&["check", &scenario("nist-grounds.toml"), "--set", "bogus=1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("--set bogus=1") && !err.contains("invalid"),
        "{err}"
    );
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\nduration_s = 5.0\nduration_s = 6.0\n").unwrap();
    let out = carfollow(&["check", bad.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains(":3:1: duplicate key `duration_s`"), "{err}");
    // One file's error is said once; of several files, the count follows.
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let good = scenario("nist-grounds.toml");
    let out = carfollow(&["check", bad.to_str().unwrap(), &good]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("1 of 2 scenario files are invalid"), "{err}");
}

/// The book's command-line reference is what the program's clap definitions give, so it
/// cannot drift from the flags that exist.
#[test]
fn the_books_command_line_reference_is_current() {
    let out = carfollow(&["cli-reference"]);
    assert!(out.status.success());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/src/reference/cli.md");
    let committed = std::fs::read_to_string(&path).unwrap();
    assert!(
        committed.as_bytes() == out.stdout.as_slice(),
        "{} is out of date: write it again with `cargo run --release -- cli-reference > \
         docs/src/reference/cli.md`",
        path.display()
    );
    for flag in [
        "--backend",
        "--rate-hz",
        "--px-per-frame",
        "--subpixel-edges",
    ] {
        assert!(committed.contains(flag), "{flag} missing");
    }
}

/// A lead that reaches its route's end stops there; the run says when, once, besides the
/// check's warning before it starts (and the run goes on with a standing lead).
#[test]
fn a_run_says_when_the_lead_reaches_the_roads_end() {
    let dir = tempfile::tempdir().unwrap();
    let out = carfollow(&[
        "run",
        "--quiet",
        "--set",
        "route.segments=[{straight_m=150}]",
        "--set",
        "route.intersections_m=[]",
        "--set",
        "duration_s=30",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(matches!(out.status.code(), Some(0 | 1)), "{err}");
    let said: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("the lead reached the route's end"))
        .collect();
    assert_eq!(said.len(), 1, "{err}");
    let t: f64 = said[0]
        .split("at t = ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no time in: {}", said[0]));
    assert!((5.0..30.0).contains(&t), "{}", said[0]);
    assert!(err.contains("stop at the road's end"), "{err}");
    // A lead that stays on its road: no such line.
    let out = run(dir.path(), &["--renderers", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("route's end"), "{err}");
}

/// `check` on a sweep file says what it is and how to check it, besides the error.
#[test]
fn check_on_a_sweep_file_points_at_the_sweeps_dry_run() {
    let sweep = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/sweeps/lambda.toml");
    let out = carfollow(&["check", sweep.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("is a sweep file") && err.contains("--dry-run"),
        "{err}"
    );
}
