//! `carfollow render` end to end: with a scenario, `--seed` replaces the scenario's seed
//! exactly as `--set seed=N` does (and is not silently ignored), and `--set` without a
//! scenario is refused with exit status 2. Run with
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
