//! Scenario files: every shipped scenario validates; bad files are refused with the file,
//! line, column and field, and what is allowed; `--set` overrides any field by its dotted path.
//! Run with `cargo test -p sim --test scenario_files`.

use sim::scenario::Scenario;
use std::path::{Path, PathBuf};

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios")
}

fn text() -> String {
    std::fs::read_to_string(scenarios_dir().join("nist-grounds.toml")).unwrap()
}

/// Loads `text` as if it were `scenarios/bad.toml`.
fn load(text: &str, overrides: &[&str]) -> Result<Scenario, String> {
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
    Scenario::load(&path, &overrides).map_err(|e| {
        // Errors are reported relative to the file name for the assertions below.
        e.to_string().replace(&dir.path().display().to_string(), "")
    })
}

/// 1-based line of the first occurrence of `needle` in the shipped text.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

#[test]
fn every_shipped_scenario_validates() {
    let mut n = 0;
    for entry in std::fs::read_dir(scenarios_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            Scenario::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 1);
    Scenario::builtin(&[]).unwrap();
}

#[test]
fn a_mistyped_field_is_named_with_its_line() {
    let t = text().replace("duration_s = 90.0", "duraton_s = 90.0");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "duraton_s");
    assert!(
        e.starts_with(&format!("/bad.toml:{line}:1: unknown field `duraton_s`")),
        "{e}"
    );
}

#[test]
fn a_wrong_type_is_named_with_its_line() {
    let t = text().replace("lambda = 0.8", "lambda = \"high\"");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "lambda =");
    assert!(e.starts_with(&format!("/bad.toml:{line}:")), "{e}");
    assert!(e.contains("invalid type") && e.contains("f64"), "{e}");
}

#[test]
fn a_negative_duration_is_refused_with_what_is_allowed() {
    let t = text().replace("duration_s = 90.0", "duration_s = -5.0");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "duration_s");
    assert_eq!(
        e,
        format!("/bad.toml:{line}:1: `duration_s` = -5: must be > 0 and at most 86400 seconds")
    );
}

#[test]
fn a_missing_target_file_is_named() {
    let t = text().replace("targets/nist-ten-segment.toml", "targets/missing.toml");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "targets/missing.toml");
    assert!(
        e.starts_with(&format!("/bad.toml:{line}:1: `tracker.target`:")),
        "{e}"
    );
    assert!(
        e.contains("missing.toml") && e.contains("cannot read"),
        "{e}"
    );
}

#[test]
fn out_of_range_values_deep_in_a_table_are_located() {
    let t = text().replace("latency_ms = 128.0", "latency_ms = -1.0");
    let e = load(&t, &[]).unwrap_err();
    assert!(
        e.starts_with(&format!(
            "/bad.toml:{}:1: `loop.latency_ms` = -1: must be 0–2000 ms",
            line_of(&t, "latency_ms")
        )),
        "{e}"
    );
    let e = load(&text(), &["tracker.lambda=1.5"]).unwrap_err();
    assert_eq!(
        e,
        "--set tracker.lambda=1.5: `tracker.lambda` = 1.5: must be in (0, 1]"
    );
}

#[test]
fn set_overrides_any_field_by_its_dotted_path() {
    let s = load(
        &text(),
        &[
            "tracker.lambda=0.7",
            "environment.sun.strength=0.5",
            "expect.gap_band_m=[4, 16]",
            "duration_s=12",
        ],
    )
    .unwrap();
    assert_eq!(s.tracker.lambda, 0.7);
    assert_eq!(s.sun.strength, 0.5);
    assert_eq!(s.expect.gap_band_m, Some([4.0, 16.0]));
    assert_eq!(s.duration_s, 12.0);
    // A new nested field (the lead driver's weave) is created on the way.
    let s = load(&text(), &["lead.driver.weave_amplitude_m=0.6"]).unwrap();
    assert_eq!(s.lead_driver.weave_amplitude_m, 0.6);
}

#[test]
fn a_bad_set_path_is_refused_and_named() {
    let e = load(&text(), &["tracker.lamda=0.7"]).unwrap_err();
    assert!(
        e.starts_with("--set tracker.lamda=0.7:") && e.contains("unknown field `lamda`"),
        "{e}"
    );
    let e = load(&text(), &["duration_s.x=1"]).unwrap_err();
    assert!(e.contains("`duration_s` is a value, not a table"), "{e}");
    let e = load(&text(), &["novalue"]).unwrap_err();
    assert!(e.contains("expected KEY.PATH=VALUE"), "{e}");
}
