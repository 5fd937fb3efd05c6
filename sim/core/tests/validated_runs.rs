//! Property: a scenario that validates is one the closed loop accepts and runs. Random
//! overrides (some inside their bounds, some beyond) go onto the shipped scenarios; each
//! that validates must build a `ClosedLoop` and run one simulated second without a panic
//! or an error: `ClosedLoop::new` refuses nothing that validation passed (the target in
//! view at t = 0 included, which validation checks with the renderer's ground truth).
//!
//! Few cases (each sets up a renderer): `VALIDATED_CASES` in CI, more with
//! `CARFOLLOW_VALIDATED_CASES=200 cargo test --release -p sim --test validated_runs`.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sim_core::{ClosedLoop, Plan};
use sim_render::Backend;
use std::path::{Path, PathBuf};

/// Cases in CI: a few seconds each at most.
const VALIDATED_CASES: u32 = 40;

fn scenario_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    paths
}

/// One override: a field and a value, drawn around and beyond its bounds.
fn an_override() -> impl Strategy<Value = String> {
    let f = |key: &'static str, lo: f64, hi: f64| (lo..hi).prop_map(move |v| format!("{key}={v}"));
    prop_oneof![
        f("lead.start_m", -5.0, 400.0),
        f("lead.initial_speed_mps", -1.0, 45.0),
        f("chase.initial_gap_m", 0.0, 80.0),
        f("camera.mount.pitch_down_deg", -20.0, 60.0),
        f("camera.mount.height_m", 0.0, 5.0),
        f("camera.focal_length_mm", 0.5, 250.0),
        f("tracker.lambda", 0.0, 1.2),
        f("tracker.zeta_px", 0.0, 20.0),
        f("loop.latency_ms", -10.0, 2500.0),
        f("loop.drop_probability", 0.0, 1.1),
        f("environment.sensor.blur_sigma_px", 0.0, 15.0),
        f("environment.sensor.noise_sigma_grey", 0.0, 80.0),
        f("environment.sensor.gain", 0.0, 25.0),
        f("environment.sun.elevation_deg", -10.0, 100.0),
        f("environment.fog.visual_range_m", -5.0, 500.0),
        f("environment.rain.rate_mm_h", -5.0, 250.0),
        (50.0..2e5f64, -5.0..1200.0f64).prop_map(|(full_well, read)| format!(
            "environment.sensor={{ shot_noise_full_well_e = {full_well}, read_noise_e = {read} }}"
        )),
        any::<bool>().prop_map(|tail| format!("lead.lamps.tail={tail}")),
        f("environment.clutter.trees_per_km", 0.0, 1200.0),
        f("lead.driver.weave_amplitude_m", -1.0, 6.0),
        f("chase.controller.gap_keeper.min_gap_m", 0.0, 20.0),
        (
            prop::sample::select(vec!["chase.controller", "lead.driver"]),
            -1.0..60.0f64,
            -1.0..12.0f64,
            0.0..120.0f64,
            0.0..220.0f64
        )
            .prop_map(|(who, base, gain, min, max)| format!(
                "{who}.lookahead={{ base_m = {base}, gain_s = {gain}, min_m = {min}, max_m = {max} }}"
            )),
        (
            prop::sample::select(vec!["chase.controller", "lead.driver"]),
            -1.0..120.0f64,
            -1.0..120.0f64,
            -1.0..60.0f64
        )
            .prop_map(|(who, kp, ki, limit)| format!(
                "{who}.speed_gains={{ kp_per_s = {kp}, ki_per_s2 = {ki}, integral_limit_mps2 = {limit} }}"
            )),
        (0usize..3_000_000).prop_map(|n| format!("chase.controller.max_breadcrumbs={n}")),
        (8.0..12_000.0f64, -400.0..400.0f64).prop_map(|(r, a)| format!(
            "route.segments=[{{ straight_m = 60 }}, {{ arc_radius_m = {r}, arc_angle_deg = {a} }}]"
        )),
    ]
}

#[test]
fn every_validated_scenario_runs_one_second() {
    let files = scenario_files();
    let backend = Backend::choose(None).unwrap();
    let cases = std::env::var("CARFOLLOW_VALIDATED_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(VALIDATED_CASES);
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            // Shrinking would set up many more renderers; the failing case is printed.
            max_shrink_iters: 0,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let strategy = (0..files.len(), prop::collection::vec(an_override(), 1..4));
    let ran = std::cell::Cell::new(0u32);
    runner
        .run(&strategy, |(which, mut overrides)| {
            overrides.push("duration_s=1".into());
            let Ok(plan) = Plan::load(&files[which], &overrides) else {
                // Refused before anything runs: nothing more to check.
                return Ok(());
            };
            let mut looped = match ClosedLoop::new(plan, backend, false) {
                Ok(l) => l,
                Err(e) => {
                    return Err(TestCaseError::fail(format!(
                        "{}: {overrides:?} validated, but the loop refused it: {e}",
                        files[which].display()
                    )))
                }
            };
            let mut frames = 0;
            while let Some(out) = looped
                .step()
                .map_err(|e| TestCaseError::fail(e.to_string()))?
            {
                prop_assert!(out.record.t_s.is_finite());
                frames += 1;
            }
            prop_assert_eq!(frames, 15);
            ran.set(ran.get() + 1);
            Ok(())
        })
        .unwrap();
    eprintln!("{} of {cases} cases validated and ran", ran.get());
    assert!(
        ran.get() > 0,
        "no case validated: the property was never tested"
    );
}

/// A change of the tracker's settings (not its target) or of `[expect]` leaves a scenario's
/// planning key as it was, and whether it plans: a sweep's pre-flight plans one point of
/// each key (`sim_core::planning_key`), and must refuse nothing less than planning each.
#[test]
fn scenarios_of_one_planning_key_plan_alike() {
    let files = scenario_files();
    let tracker_or_expect = prop_oneof![
        (0.01..0.99f64).prop_map(|v| format!("tracker.lambda={v}")),
        (1.0..40.0f64).prop_map(|v| format!("tracker.delta_deg={v}")),
        (0.5..10.0f64).prop_map(|v| format!("tracker.zeta_px={v}")),
        prop::sample::select(vec!["tracker.mode=\"paper\"", "tracker.mode=\"robust\""])
            .prop_map(String::from),
        (0.0..100.0f64).prop_map(|v| format!("expect.max_lost_s={v}")),
    ];
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: 30,
            failure_persistence: None,
            max_shrink_iters: 0,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let strategy = (
        0..files.len(),
        prop::collection::vec(an_override(), 0..3),
        prop::collection::vec(tracker_or_expect, 1..3),
    );
    runner
        .run(&strategy, |(which, base, extra)| {
            let Ok(a) = sim_core::Scenario::load(&files[which], &base) else {
                return Ok(());
            };
            let both: Vec<String> = base.iter().chain(&extra).cloned().collect();
            let Ok(b) = sim_core::Scenario::load(&files[which], &both) else {
                return Ok(());
            };
            prop_assert_eq!(sim_core::planning_key(&a), sim_core::planning_key(&b));
            prop_assert_eq!(Plan::new(&a).is_ok(), Plan::new(&b).is_ok(), "{:?}", both);
            Ok(())
        })
        .unwrap();
}

/// What decides planning does change the key: the seed (the scenery), the camera, the
/// target file.
#[test]
fn the_planning_key_follows_what_decides_planning() {
    let key = |set: &[&str]| {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        sim_core::planning_key(&sim_core::Scenario::builtin(&set).unwrap())
    };
    let base = key(&[]);
    assert_eq!(base, key(&["tracker.lambda=0.7", "expect.max_lost_s=3"]));
    assert_ne!(base, key(&["seed=2"]));
    assert_ne!(base, key(&["camera.mount.pitch_down_deg=5"]));
    assert_ne!(base, key(&["environment.clutter.trees_per_km=10"]));
}
