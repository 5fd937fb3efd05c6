//! The truth's `low_contrast`: a target too faint for the paper's edge threshold in the
//! pixels the tracker read is no false alarm, and its loss is said to be the contrast's.
//! `strong-shadows` in the paper's mode: the board passes under tree shadows from 7 s and
//! lies in deep shadow from about 20 s, where the paper's threshold no longer sees it;
//! `night`: the first frames are dark until the automatic gain brings the board up;
//! `car-ahead` in fog: an actor in the path, judged on its own model. Run
//! with `cargo test --release -p sim --test low_contrast`.

mod osc_common;

use osc_common::{frames_of, Frames};
use std::path::{Path, PathBuf};

fn scenario(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenarios/{name}.toml"))
}

/// The frames of scenario `name` run into `out` with each of `set` as a `--set`.
fn run(name: &str, set: &[&str], out: &Path) -> Frames {
    let extra: Vec<&str> = set.iter().flat_map(|s| ["--set", s]).collect();
    Frames::parse(&frames_of(&scenario(name), out, &extra))
}

/// The rows of `f` whose column `name` holds `value`.
fn rows_with<'f>(f: &'f Frames, name: &str, value: &str) -> Vec<&'f [String]> {
    let col = f.header.iter().position(|h| h == name).unwrap();
    f.rows
        .iter()
        .filter(|r| r[col] == value)
        .map(Vec::as_slice)
        .collect()
}

/// The times of `rows`.
fn times(f: &Frames, rows: &[&[String]]) -> Vec<f64> {
    rows.iter().map(|r| f.num(r, "t_s")).collect()
}

#[test]
fn a_board_in_deep_shadow_is_lost_to_its_contrast_and_shadows_raise_no_false_alarm() {
    let dir = tempfile::tempdir().unwrap();
    let set = ["tracker.mode=\"paper\"", "duration_s=25"];
    let f = run("strong-shadows", &set, &dir.path().join("shadows"));
    let faint = times(&f, &rows_with(&f, "loss_cause", "low_contrast"));
    // Lost to the contrast as the board goes into the deep shadow, and only then.
    assert!(faint.len() >= 3, "{faint:?}");
    assert!(
        faint.iter().all(|&t| (20.0..22.0).contains(&t)),
        "{faint:?}"
    );
    // The shadows crossing the board before dim it below the threshold in many frames;
    // the status saying so there is no false alarm (there were 3.2 s of them to 20.4 s).
    let alarms = rows_with(&f, "false_alarm", "1").len();
    assert!(alarms <= 20, "{alarms} frames of false alarm");
}

#[test]
fn the_dark_first_frames_of_the_night_raise_no_false_alarm() {
    let dir = tempfile::tempdir().unwrap();
    for mode in ["paper", "robust"] {
        let set = [
            format!("tracker.mode=\"{mode}\""),
            "duration_s=3".to_string(),
        ];
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        let f = run("night", &set, &dir.path().join(mode));
        let alarms = times(&f, &rows_with(&f, "false_alarm", "1"));
        assert!(alarms.is_empty(), "{mode}: false alarms at {alarms:?}");
    }
}

#[test]
fn an_actor_in_the_path_too_faint_in_fog_is_lost_to_its_contrast() {
    // `car-ahead` in fog of 60 m: the car 14 m ahead in the chase's lane, the paper's mode
    // losing it. The frames judged on the car's own model.
    let dir = tempfile::tempdir().unwrap();
    let set = [
        "tracker.mode=\"paper\"",
        "environment.fog.visual_range_m=60",
    ];
    let f = run("car-ahead", &set, dir.path());
    let path = f.header.iter().position(|h| h == "path_vehicle").unwrap();
    let faint = rows_with(&f, "loss_cause", "low_contrast");
    for r in &faint {
        assert_eq!(r[path], "car");
    }
    // 16 frames on 30 November 2026 (91 before the car's back was judged only at scales
    // where its nearest parallel edges lie 4 px apart or more).
    assert!(
        faint.len() >= 10,
        "{} frames lost to the car's contrast",
        faint.len()
    );
}
