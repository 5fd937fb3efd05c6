//! The scenario library's `[expect]` criteria as a regression suite: a change that worsens
//! following distance, tracking loss or path deviation in any shipped scenario fails CI.
//!
//! CI runs every scenario shortened to its first [`SHORT_S`] seconds (the distance criterion
//! scaled to match), except the 17-minute tape, which always runs whole: holding the target
//! for all of it is the paper's headline result. The full-length suite runs with
//! `CARFOLLOW_FULL=1 cargo test --release -p carfollow-tests --test regression`.

use sim::camera::Backend;
use sim::closed_loop::ClosedLoop;
use sim::report::Summary;
use sim::scenario::Scenario;
use std::path::{Path, PathBuf};

/// Length of each scenario in the short suite, seconds.
const SHORT_S: f64 = 20.0;

fn scenario_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(format!("{name}.toml"))
}

fn full() -> bool {
    std::env::var("CARFOLLOW_FULL").is_ok_and(|v| v == "1")
}

/// Runs a scenario (shortened unless `whole` or the full suite was asked for) and returns
/// its summary.
fn run(name: &str, whole: bool) -> Summary {
    let path = scenario_path(name);
    let full_length = Scenario::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut overrides = Vec::new();
    if !whole && !full() && full_length.duration_s > SHORT_S {
        overrides.push(format!("duration_s={SHORT_S}"));
        if let Some(d) = full_length.expect.min_distance_m {
            overrides.push(format!(
                "expect.min_distance_m={}",
                d * SHORT_S / full_length.duration_s
            ));
        }
    }
    let scenario = Scenario::load(&path, &overrides).unwrap_or_else(|e| panic!("{e}"));
    let mut looped = ClosedLoop::new(&scenario, Backend::choose(None).unwrap(), false).unwrap();
    let mut records = Vec::new();
    while let Some(out) = looped.step().unwrap() {
        records.push(out.record);
    }
    Summary::compute(
        &scenario.name,
        scenario.seed,
        &records,
        &scenario.expect,
        0.0,
    )
}

macro_rules! scenario_test {
    ($test:ident, $name:literal) => {
        #[test]
        fn $test() {
            let s = run($name, false);
            assert!(
                s.passed,
                "{} failed its [expect]:\n  {}",
                $name,
                s.failures.join("\n  ")
            );
        }
    };
}

scenario_test!(nist_grounds, "nist-grounds");
scenario_test!(weave, "weave");
scenario_test!(hard_braking, "hard-braking");
scenario_test!(long_range, "long-range");
scenario_test!(close_range, "close-range");
scenario_test!(strong_shadows, "strong-shadows");
scenario_test!(poles_and_buildings, "poles-and-buildings");

/// The 17-minute tape, whole: 15,300 frames, about half a minute of wall time.
#[test]
fn tape_17min() {
    let s = run("tape-17min", true);
    assert!(
        s.passed,
        "tape-17min failed its [expect]:\n  {}",
        s.failures.join("\n  ")
    );
}
