//! `carfollow run` end to end: two renderers (the second in a worker process) give the same
//! outputs as one; the exit status follows the `[expect]` verdict; bad input exits 2 with a
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

#[test]
fn bad_arguments_exit_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for (extra, needle) in [
        (&["--renderers", "3"][..], "--renderers"),
        (&["--set", "tracker.lamda=0.7"][..], "tracker.lamda"),
        (&["no-such-scenario.toml"][..], "no-such-scenario.toml"),
    ] {
        let out = run(dir.path(), extra);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{extra:?}: {err}");
    }
}
