//! The scenario library's `[expect]` criteria as a regression suite: a change that worsens
//! following distance, tracking loss or path deviation in any shipped scenario fails CI.
//!
//! CI runs every scenario whole, so that each one's defining event happens (`hard-braking`'s
//! first stop comes at 20.1 s, its second at 45.1 s; the 17-minute tape is the paper's
//! headline result): in release builds the library's 60–90 s scenarios take 2–3 s each and
//! the tape about 30 s. Every scenario also runs in robust mode (`tracker.mode = "robust"`),
//! which must pass the same `[expect]`, and every run checks that no loss went unreported
//! for more than 15 frames.

use sim::Summary;
use sim_core::ClosedLoop;
use sim_core::Plan;
use sim_render::Backend;
use std::path::{Path, PathBuf};

fn scenario_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(format!("{name}.toml"))
}

fn run(name: &str) -> Summary {
    run_with(name, &[])
}

/// As [`run`], with more overrides (`tracker.mode=robust`, say).
fn run_with(name: &str, extra: &[&str]) -> Summary {
    let path = scenario_path(name);
    let overrides: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let plan = Plan::load(&path, &overrides).unwrap_or_else(|e| panic!("{e}"));
    let summary = run_scenario(plan);
    eprintln!(
        "{name} {extra:?}: passed {}, lost {:.2} s, silent {} frames, false alarm {:.2} s \
         (longest {} frames), unresolved {:?}",
        summary.passed,
        summary.tracking_lost_s,
        summary.silent_loss_frames,
        summary.false_alarm_s,
        summary.longest_false_alarm_frames,
        summary.unresolved.first().map(|e| e.t_s)
    );
    // In every mode and scenario, a loss is never silent for long: the tracker's own status
    // leaves `tracking` within 15 frames of the truth's loss.
    if let Some(delay) = summary.max_loss_report_delay_frames {
        assert!(
            delay <= 15,
            "{name} {extra:?}: the tracker said `tracking` for {delay} frames after a loss"
        );
    }
    summary
}

fn run_scenario(plan: Plan) -> Summary {
    let scenario = plan.scenario().clone();
    let mut looped = ClosedLoop::new(plan, Backend::choose(None).unwrap(), false).unwrap();
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
            let s = run($name);
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
scenario_test!(nist_grounds_manual, "nist-grounds-manual");
scenario_test!(weave, "weave");
scenario_test!(hard_braking, "hard-braking");
scenario_test!(long_range, "long-range");
scenario_test!(close_range, "close-range");
scenario_test!(strong_shadows, "strong-shadows");
scenario_test!(poles_and_buildings, "poles-and-buildings");

/// The 17-minute tape, whole: 15,300 frames, about half a minute of wall time.
#[test]
fn tape_17min() {
    let s = run("tape-17min");
    assert!(
        s.passed,
        "tape-17min failed its [expect]:\n  {}",
        s.failures.join("\n  ")
    );
}

scenario_test!(intersections, "intersections");
scenario_test!(stop_and_go, "stop-and-go");
scenario_test!(gravel_road, "gravel-road");
scenario_test!(swerves, "swerves");
scenario_test!(section4, "section4");
scenario_test!(highway_90, "highway-90");
scenario_test!(low_sun_trees, "low-sun-trees");
scenario_test!(cut_in, "cut-in");
scenario_test!(cut_out, "cut-out");
scenario_test!(next_lane_traffic, "next-lane-traffic");
scenario_test!(slow_vehicle_ahead, "slow-vehicle-ahead");
scenario_test!(far_lead, "far-lead");
scenario_test!(stopped_car_ahead, "stopped-car-ahead");
scenario_test!(fog, "fog");
scenario_test!(night, "night");
scenario_test!(rain, "rain");
scenario_test!(opendrive_curves, "opendrive-curves");
scenario_test!(divided_highway, "divided-highway");
scenario_test!(ncap_ccrs, "ncap-ccrs");
scenario_test!(ncap_ccrm, "ncap-ccrm");
scenario_test!(ncap_ccrb, "ncap-ccrb");

macro_rules! robust_test {
    ($test:ident, $name:literal) => {
        /// The scenario in robust mode (`tracker.mode = "robust"`), at its own λ: robust
        /// mode must pass every `[expect]` of the library.
        #[test]
        fn $test() {
            let s = run_with($name, &["tracker.mode=robust"]);
            assert!(
                s.passed,
                "{} failed its [expect] in robust mode:\n  {}",
                $name,
                s.failures.join("\n  ")
            );
        }
    };
}

robust_test!(robust_nist_grounds, "nist-grounds");
robust_test!(robust_nist_grounds_manual, "nist-grounds-manual");
robust_test!(robust_section4, "section4");
robust_test!(robust_weave, "weave");
// Whole: both of its emergency stops (from 20.1 s) are what robust mode must hold.
robust_test!(robust_hard_braking, "hard-braking");
robust_test!(robust_long_range, "long-range");
robust_test!(robust_close_range, "close-range");
robust_test!(robust_poles_and_buildings, "poles-and-buildings");
robust_test!(robust_tape_17min, "tape-17min");
robust_test!(robust_intersections, "intersections");
robust_test!(robust_stop_and_go, "stop-and-go");
robust_test!(robust_highway_90, "highway-90");
robust_test!(robust_cut_in, "cut-in");
robust_test!(robust_cut_out, "cut-out");
robust_test!(robust_next_lane_traffic, "next-lane-traffic");
robust_test!(robust_slow_vehicle_ahead, "slow-vehicle-ahead");
robust_test!(robust_far_lead, "far-lead");
robust_test!(robust_stopped_car_ahead, "stopped-car-ahead");
robust_test!(robust_fog, "fog");
robust_test!(robust_night, "night");
robust_test!(robust_rain, "rain");
robust_test!(robust_opendrive_curves, "opendrive-curves");
robust_test!(robust_divided_highway, "divided-highway");
robust_test!(robust_ncap_ccrs, "ncap-ccrs");
robust_test!(robust_ncap_ccrm, "ncap-ccrm");
robust_test!(robust_ncap_ccrb, "ncap-ccrb");

/// `low-sun-trees`: the low sun's long shadow brings the paper's mode to say `lost` early
/// and lose the target for a moment, within the scenario's `[expect]`; robust mode, whose
/// threshold follows the light down, holds it with no loss and no time out of the gap band.
#[test]
fn robust_mode_holds_the_low_sun_through_trees_with_no_loss() {
    let s = run_with("low-sun-trees", &["tracker.mode=robust"]);
    assert!(
        s.passed,
        "low-sun-trees failed its [expect] in robust mode:\n  {}",
        s.failures.join("\n  ")
    );
    assert_eq!(s.tracking_lost_s, 0.0, "robust mode lost the target");
    assert_eq!(s.tracking_loss_events, 0);
    assert_eq!(s.time_outside_gap_band_s, 0.0);
}

/// Without its pan head, `intersections`' first right-angle turn takes the target out of
/// the fixed camera's view: the loss is put down to `out_of_view`, the failure says so, and
/// the chase, stopped on the lead's path, is measured against the part of the path where it
/// stands (it once read 138 m, from the wrong part of the path). (The paper's tracker goes
/// on saying `tracking` for a few seconds on whatever edges the window holds once the target
/// has left it, so the loss-report check of `run_with` does not apply.)
#[test]
fn a_fixed_camera_loses_the_right_angle_turn_out_of_view() {
    let overrides = [
        "camera.pan.enabled=false".to_string(),
        "duration_s=40".into(),
    ];
    let plan =
        Plan::load(&scenario_path("intersections"), &overrides).unwrap_or_else(|e| panic!("{e}"));
    let s = run_scenario(plan);
    assert!(
        s.lost_by_cause_s.out_of_view > 5.0,
        "out of view only {:?}",
        s.lost_by_cause_s
    );
    assert!(
        s.loss_events
            .iter()
            .any(|e| e.cause == sim_core::LossCause::OutOfView),
        "{:?}",
        s.loss_events
    );
    let lost = s
        .failures
        .iter()
        .find(|f| f.starts_with("tracking lost"))
        .expect("a loss failure");
    assert!(lost.contains("s out_of_view"), "{lost}");
    assert!(
        s.lateral_path_error_m.max_abs < 1.0,
        "deviation {:.2} m",
        s.lateral_path_error_m.max_abs
    );
}

/// The paper's mode loses the gravel road, the swerves and the strong shadows (the
/// scenarios that run in robust mode: section 4's abrupt motion and shadows), and says so:
/// `run_with` checks that every loss was reported within 15 frames.
#[test]
fn the_paper_mode_loses_the_robust_modes_scenarios_and_says_so() {
    for name in ["gravel-road", "swerves", "strong-shadows"] {
        let s = run_with(name, &["tracker.mode=paper"]);
        assert!(
            s.tracking_lost_s > 5.0,
            "{name}: the paper's mode lost only {:.2} s",
            s.tracking_lost_s
        );
        assert!(
            s.silent_loss_frames <= 15,
            "{name}: {} silent frames",
            s.silent_loss_frames
        );
    }
}

/// Robust mode re-acquires in the loop: the teleoperator's placement 40 px off the target
/// (more than the paper's window can absorb) fails the check, robust mode finds the target
/// by search within a few frames (a `reacquired` event), and the chase follows.
#[test]
fn robust_mode_reacquires_after_a_misplaced_start_and_the_chase_follows() {
    let s = run_with(
        "nist-grounds",
        &[
            "tracker.mode=robust",
            "duration_s=15",
            "tracker.init_offset=[40, 0, 0]",
        ],
    );
    assert!(
        s.reacquired
            .iter()
            .any(|e| e.event == "reacquired" && e.t_s < 1.0),
        "no early re-acquisition: {:?}",
        s.reacquired
    );
    assert!(s.tracking_lost_s < 0.5, "lost {:.2} s", s.tracking_lost_s);
    assert!(
        s.distance_m > 100.0,
        "the chase drove only {:.1} m",
        s.distance_m
    );
}

/// `highway-90` with the paper's 8 mm lens: at 25 m the target is 28 px wide, its
/// horizontal features 3.2 px apart, near the 3 px at which stage 1 merges them and within
/// the prediction's error at speed (`tracker::resolvability`). Each mode must say so (no more than 15
/// frames of silent loss, and no frame of `tracking` more than 15 frames into the truth's
/// loss), and the chase must then stop under control (the loss's 3.5 m/s²,
/// `loss_decel_mps2`), never braking fully: the lead drives on at 90 km/h, so no real
/// closing is ever measured. (Robust mode reported `tracking` for 24 frames with the range
/// 25-50 % short, and braked fully for 0.4 s, before the resolution check.)
#[test]
fn at_90_kmh_with_the_8_mm_lens_a_loss_brings_a_controlled_stop_in_both_modes() {
    for mode in ["paper", "robust"] {
        let overrides = [
            "camera.focal_length_mm=8".to_string(),
            format!("tracker.mode={mode}"),
        ];
        let plan =
            Plan::load(&scenario_path("highway-90"), &overrides).unwrap_or_else(|e| panic!("{e}"));
        let scenario = plan.scenario().clone();
        let mut looped = ClosedLoop::new(plan, Backend::choose(None).unwrap(), false).unwrap();
        let mut records = Vec::new();
        while let Some(out) = looped.step().unwrap() {
            records.push(out.record);
        }
        let s = Summary::compute(
            &scenario.name,
            scenario.seed,
            &records,
            &scenario.expect,
            0.0,
        );
        assert!(
            s.tracking_lost_s > 1.0,
            "{mode}: the 8 mm lens held the target ({} s lost)",
            s.tracking_lost_s
        );
        assert!(
            s.max_loss_report_delay_frames.unwrap_or(0) <= 15,
            "{mode}: the loss went unreported for {:?} frames",
            s.max_loss_report_delay_frames
        );
        assert!(
            s.silent_loss_frames <= 15,
            "{mode}: {} frames reported tracking while lost",
            s.silent_loss_frames
        );
        let full: Vec<f64> = records
            .iter()
            .filter(|r| r.brake >= 0.99)
            .map(|r| r.t_s)
            .collect();
        assert!(
            full.is_empty(),
            "{mode}: full brake at {full:?} s with no closing"
        );
        let stop = records
            .iter()
            .find(|r| r.chase_mode == "stopping")
            .unwrap_or_else(|| panic!("{mode}: the chase does not stop after the loss"));
        assert!(
            stop.chase_speed_mps > 15.0,
            "{mode}: stopping from {} m/s",
            stop.chase_speed_mps
        );
        // Over any second, the chase slows by no more than the loss's 3.5 m/s² and a margin
        // for the brake's build-up (measured: 3.6 m/s²).
        let worst = records
            .windows(16)
            .map(|w| (w[0].chase_speed_mps - w[15].chase_speed_mps) / (w[15].t_s - w[0].t_s))
            .fold(0.0, f64::max);
        assert!(
            worst <= 4.5,
            "{mode}: decelerated at {worst:.2} m/s² over a second"
        );
        assert!(
            records.last().unwrap().chase_speed_mps < 0.5,
            "{mode}: the chase did not stop"
        );
    }
}

/// Euro NCAP's CCRm through the 16 mm lens, from the sweep's 70 m: the standing start finds
/// the lead's board 55-70 m ahead, beyond the search's smallest scale, where the model fits
/// its outline about the board at 1.6 times the board's scale. That fit is refused
/// (`tracker::robust::NESTED_FIT_RATIO`) and the board is held at its own scale once the
/// search reaches it: no more than 15 frames say `tracking` off the board. (Before, the
/// fit was held and the chase followed a target it took for 35 m ahead: 77 silent frames at
/// 40 km/h in robust mode, 31 at 60 km/h in the paper's.)
#[test]
fn ncap_ccrm_through_the_16_mm_lens_holds_no_board_at_a_larger_scale() {
    ccrm_16_mm_holds_the_board(&[("11.11", "robust"), ("16.67", "paper")]);
}

/// `ncap-ccrm` through the 16 mm lens from 70 m, at each `(cruise speed m/s, tracker mode)`
/// of `points`: no more than 15 frames say `tracking` off the board, and `[expect]` passes.
fn ccrm_16_mm_holds_the_board(points: &[(&str, &str)]) {
    for (speed_mps, mode) in points {
        let s = run_with(
            "ncap-ccrm",
            &[
                "duration_s=30",
                "chase.initial_gap_m=70",
                "camera.focal_length_mm=16",
                &format!("chase.controller.cruise_speed_mps={speed_mps}"),
                &format!("tracker.mode={mode}"),
            ],
        );
        assert!(
            s.silent_loss_frames <= 15,
            "{mode} at {speed_mps} m/s: {} frames said `tracking` off the board",
            s.silent_loss_frames
        );
        assert!(s.passed, "{mode} at {speed_mps} m/s: {:?}", s.failures);
    }
}

/// `stopped-car-ahead` on other seeds (other clutter and noise), as the traffic guide
/// reports them: the chase finds the standing car and never touches it, in both modes. A
/// weak fit rechecked more rarely in robust mode (one frame in 3, then 6, then 12) made two
/// of these five seeds end in contact (36 and 15 km/h) while the scenario's own seed passed.
#[test]
fn a_car_standing_ahead_is_never_touched_on_seeds_1_to_5_in_either_mode() {
    for mode in ["paper", "robust"] {
        for seed in 1..=5 {
            let s = run_with(
                "stopped-car-ahead",
                &[&format!("tracker.mode={mode}"), &format!("seed={seed}")],
            );
            let traffic = s.traffic.expect("a traffic scenario's summary");
            assert_eq!(
                traffic.impact_speed_kph, None,
                "{mode}, seed {seed}: the chase hit the standing car"
            );
        }
    }
}

/// A fit whose range shrinks faster than the chase drives has slid off its target
/// (`sim_core`'s `plugin::closing`), and the lane is searched for the target at once. In
/// `ncap-ccrm` through the 16 mm lens the board, found 53.7 m ahead and too small to
/// resolve, is coasted on, and the fit slides to the lead's whole back, a range of 25 m:
/// robust mode at 55 km/h said `tracking` there for 18 frames before the check, and the
/// paper's mode at 50 km/h lost the board for 16.5 s and failed its criteria.
#[test]
fn a_fit_closing_faster_than_the_chase_drives_gives_way_to_the_target() {
    ccrm_16_mm_holds_the_board(&[("15.28", "robust"), ("13.89", "paper")]);
}

/// A contact's closing speed is the speed the chase came in at, not what the physics step
/// that made the contact left of it: in `ncap-ccrs` at 45 km/h with 50 % overlap (the
/// paper's mode, its sweep's CCRs test that ends in contact) the chase hits the standing car
/// still doing most of its speed of the frame before (until 2026-11-27 this read
/// -4.7 km/h).
#[test]
fn a_contact_is_measured_at_the_speed_the_chase_came_in_at() {
    let set = [
        "chase.controller.cruise_speed_mps=12.5".to_string(),
        "lead.offset_m=1.0".to_string(),
    ];
    let plan = Plan::load(&scenario_path("ncap-ccrs"), &set).unwrap_or_else(|e| panic!("{e}"));
    let mut looped = ClosedLoop::new(plan, Backend::choose(None).unwrap(), false).unwrap();
    let mut before_kph = None;
    let mut contact = None;
    while let Some(out) = looped.step().unwrap() {
        let r = out.record;
        let first = r.traffic.as_ref().and_then(|t| t.contacts.first().cloned());
        if let Some(c) = first {
            contact = Some(c);
            break;
        }
        before_kph = Some(r.chase_speed_mps * 3.6);
    }
    let contact =
        contact.expect("ncap-ccrs at 45 km/h, 50 % overlap, ends in contact in paper mode");
    let before_kph = before_kph.unwrap();
    let closing_kph = contact.closing_mps * 3.6;
    // At most a frame of braking at 8.1 m/s² (2.0 km/h) between the two.
    assert!(
        closing_kph > before_kph - 3.0 && closing_kph <= before_kph + 0.5,
        "contact closing at {closing_kph:.1} km/h; the frame before, {before_kph:.1} km/h"
    );
}
