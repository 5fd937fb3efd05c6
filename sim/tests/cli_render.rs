//! `carfollow render` end to end: with a scenario, `--seed` replaces the scenario's seed
//! exactly as `--set seed=N` does (and is not silently ignored), and `--set` without a
//! scenario and a time past the run's last frame are refused with exit status 2. Run with
//! `cargo test --release -p sim --test cli_render`.

use std::path::Path;
use std::process::{Command, Output};

fn render(out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .arg("render")
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn weave() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios/weave.toml")
        .to_str()
        .unwrap()
        .to_owned()
}

#[test]
fn seed_replaces_the_scenarios_seed() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = weave();
    let frame = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec![scenario.as_str(), "--time", "1"];
        args.extend(extra);
        let done = render(&out, &args);
        assert!(
            done.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&done.stderr)
        );
        std::fs::read(out).unwrap()
    };
    let own = frame("own.png", &[]);
    let seeded = frame("seeded.png", &["--seed", "3"]);
    let set = frame("set.png", &["--set", "seed=3"]);
    assert_eq!(seeded, set, "--seed 3 and --set seed=3 differ");
    assert_ne!(own, seeded, "--seed 3 rendered the scenario's own seed");
}

#[test]
fn set_without_a_scenario_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let done = render(&dir.path().join("f.png"), &["--set", "seed=3"]);
    assert_eq!(done.status.code(), Some(2));
    let err = String::from_utf8_lossy(&done.stderr);
    assert!(err.contains("--set seed=3"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

/// A time whose nearest frame is past the run's last is refused before the run, with exit
/// status 2: `--time 59.99` of the 60 s `weave` (frames at k / 15 s, the last at 59.933 s)
/// as `--time 200`; the last frame itself renders.
#[test]
fn a_time_past_the_last_frame_is_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f.png");
    for time in ["59.99", "60", "200"] {
        let done = render(&out, &[&weave(), "--time", time]);
        let err = String::from_utf8_lossy(&done.stderr);
        assert_eq!(done.status.code(), Some(2), "{time}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("past the last frame"), "{err}");
        assert!(err.contains("59.933 s"), "{err}");
        assert!(!out.exists());
    }
    let done = render(&out, &[&weave(), "--time", "59.94"]);
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
    assert!(String::from_utf8_lossy(&done.stdout).contains("t = 59.933 s"));
}

/// A shadow distractor puts a shadow's edge on the board at its offset from the feature: 3 px
/// (at the nominal range) outside the outer left feature of `section4`, seen in the frame
/// against the same frame with the distractor invisible.
#[test]
fn a_shadow_distractor_puts_its_edge_at_the_offset() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios/section4.toml")
        .to_str()
        .unwrap()
        .to_owned();
    let frame = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec![
            scenario.as_str(),
            "--time",
            "3",
            "--set",
            "environment.sun.soft_shadows=true",
        ];
        args.extend(extra);
        let done = render(&out, &args);
        assert!(
            done.status.success(),
            "{}",
            String::from_utf8_lossy(&done.stderr)
        );
        let said = String::from_utf8_lossy(&done.stdout).to_string();
        (image::open(&out).unwrap().into_luma8(), said)
    };
    let (shadowed, said) = frame(
        "shadow.png",
        &[
            "--set",
            "environment.distractors.0.kind=\"shadow\"",
            "--set",
            "environment.distractors.0.offset_px=3",
        ],
    );
    let (plain, _) = frame(
        "plain.png",
        &["--set", "environment.distractors.0.albedo=0.85"],
    );
    // "target c = (X, Y) px, scale S": the outer left feature is 0.8 m × 32 px/m × S left.
    let numbers: Vec<f64> = said
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|t| t.parse().ok())
        .collect();
    let at = said
        .find("target c = (")
        .expect("the target's place is printed");
    let tail: Vec<f64> = said[at..]
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|t| t.parse().ok())
        .collect();
    assert!(numbers.len() >= 3);
    let (cx, cy, scale) = (tail[0], tail[1], tail[2]);
    let feature = cx - 0.8 * 32.0 * scale;
    let row = cy.round() as u32;
    // Walking out from the feature over the board's light margin, the shadow's edge is
    // where the frame stops (or starts) being darker than without the shadow; the band
    // lies on one side of it or the other, as the sun falls.
    let darker = |x: u32| {
        f64::from(shadowed.get_pixel(x, row)[0]) + 40.0 < f64::from(plain.get_pixel(x, row)[0])
    };
    let first = feature.floor() as u32 - 1;
    assert!(
        f64::from(plain.get_pixel(first, row)[0]) > 120.0,
        "not on the margin"
    );
    let edge = (0..first)
        .rev()
        .find(|&x| darker(x) != darker(first))
        .expect("a shadow edge on the board's margin") as f64;
    let offset = feature - (edge + 0.5);
    assert!(
        (offset - 3.0 * scale).abs() < 1.5,
        "shadow edge {offset:.2} px outside the feature, wanted {:.2}",
        3.0 * scale
    );
}

/// A negative `--time` reaches the validator (exit 2, one line), as `--time=-1` does,
/// rather than clap's advice; a time between two frames of a run says which frame it
/// rendered.
#[test]
fn a_negative_time_is_refused_and_a_time_between_frames_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f.png");
    for time in [&["--time", "-1"][..], &["--time=-1"][..]] {
        let mut args = vec![weave()];
        args.extend(time.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let done = render(&out, &args);
        let err = String::from_utf8_lossy(&done.stderr);
        assert_eq!(done.status.code(), Some(2), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("--time must be"), "{err}");
    }
    let done = render(&out, &[&weave(), "--time", "0.03"]);
    let err = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "{err}");
    assert!(err.contains("rendering frame 0, t = 0.000 s"), "{err}");
}
