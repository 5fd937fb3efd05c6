//! A ghost must not be reported as tracking (issue 37). The target swerves 30 px sideways in
//! 3 frames past a telephone pole and a wire that stand still in the image. The paper's
//! tracker cannot follow so abrupt a motion (section 4's trade-off): its fit stays 30 px
//! beside the target, two feature spacings at scale 1.2, with the model's features on the
//! target's other features and on the pole. After a swerve to the right that fit covers a
//! third of its outline horizontally and 0.8 vertically (the true fit 0.87 and 0.90 before
//! it): enough for the absolute coverage check, and no move of one feature spacing or 5 px
//! covers more. Judged by those checks alone, the paper's mode said `tracking` on it for up
//! to 79 frames in a row (73–79 on every swerve to the right, seeds 1–10). The promise of
//! both modes is at most [`MAX_SILENT_FRAMES`] frames in a row of `tracking` while the
//! estimate is more than 5 px or 10 % in scale from the truth; the check against the
//! track's own reference coverage (`tracker::robust::CoverageReference`) keeps it.
//!
//! The paper's mode's estimates stay the paper's: only its status changed, and the status
//! never feeds back into them (checked here too).
//!
//! Run with `cargo test -p tracker --release --test swerve_ghost -- --nocapture`.

use tracker::synth::{clutter_scene, draw, nist_ten_segment, SynthScene};
use tracker::{
    Camera, GrayView, Location, Status, TrackOutput, Tracker, TrackerConfig, TrackerMode,
};

/// The longest run of frames a tracker may say `tracking` while off the target.
const MAX_SILENT_FRAMES: usize = 15;
const FRAMES: usize = 180;
/// Swerves (odd seeds to the right, even ones to the left).
const SWERVE_SEEDS: u64 = 4;
/// Off the target: farther than this from the truth's centre, pixels ...
const OFF_PX: f64 = 5.0;
/// ... or off in scale by more than this fraction.
const OFF_SCALE: f64 = 0.1;

/// The swerve of `seed`: at scale 1.2 around (128, 112), from 15 px on one side to 15 px on
/// the other over frames 20–23 (odd seeds to the right, even ones to the left), with a
/// gentle vertical bob; and its scenes: noise σ = 2, and a pole and a wire placed as
/// `synth::clutter_scene` places them beside the target at the swerve's midpoint, where
/// they stay.
fn swerve(seed: u64) -> (Vec<Location>, Vec<SynthScene>) {
    let half = half_extent();
    let side = if seed % 2 == 1 { 1.0 } else { -1.0 };
    let truth: Vec<Location> = (0..FRAMES)
        .map(|k| {
            let progress = ((k as f64 - 20.0) / 3.0).clamp(0.0, 1.0);
            Location::new(
                128.0 + side * (30.0 * progress - 15.0),
                112.0 + 2.0 * (0.05 * k as f64 + seed as f64).sin(),
                1.2,
            )
        })
        .collect();
    let mid = Location::new(128.0, 112.0, 1.2);
    let scenes = (0..FRAMES)
        .map(|k| SynthScene {
            noise_sigma: 2.0,
            shadows: Vec::new(),
            ..clutter_scene(k, mid, half)
        })
        .collect();
    (truth, scenes)
}

fn half_extent() -> [f64; 2] {
    let model = nist_ten_segment();
    let camera = Camera::default();
    model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m())
}

fn run(
    config: TrackerConfig,
    truth: &[Location],
    scenes: &[SynthScene],
    seed: u64,
) -> Vec<TrackOutput> {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let mut tracker = Tracker::new(model.clone(), camera, config, truth[0]).unwrap();
    truth
        .iter()
        .zip(scenes)
        .enumerate()
        .map(|(k, (at, scene))| {
            let px = draw(&model, &camera, *at, scene, seed * 1_000_003 + k as u64);
            tracker.step(
                GrayView::new(scene.width, scene.height, &px).unwrap(),
                k as f64 / 15.0,
            )
        })
        .collect()
}

fn off(out: &TrackOutput, at: &Location) -> bool {
    let e = out.estimate;
    (e.c_x - at.c_x).hypot(e.c_y - at.c_y) > OFF_PX || (e.scale / at.scale - 1.0).abs() > OFF_SCALE
}

#[test]
fn a_fit_beside_the_target_after_a_swerve_is_not_called_tracking() {
    let mut ghosts = 0;
    for mode in [TrackerMode::Paper, TrackerMode::Robust] {
        for lambda in [0.5, 0.8] {
            for seed in 1..=SWERVE_SEEDS {
                let (truth, scenes) = swerve(seed);
                let config = TrackerConfig {
                    mode,
                    lambda,
                    ..TrackerConfig::default()
                };
                let outputs = run(config, &truth, &scenes, seed);
                let (mut run_len, mut longest, mut end, mut off_frames) = (0, 0, 0, 0);
                for (k, (out, at)) in outputs.iter().zip(&truth).enumerate() {
                    let off = off(out, at);
                    off_frames += usize::from(off);
                    if off && out.status == Status::Tracking {
                        run_len += 1;
                        if run_len > longest {
                            (longest, end) = (run_len, k);
                        }
                    } else {
                        run_len = 0;
                    }
                }
                let name = format!("{} λ = {lambda} seed {seed}", mode.as_str());
                eprintln!(
                    "{name}: {off_frames} frames off the target; longest run of `tracking` \
                     while off: {longest} (to frame {end})"
                );
                // The scene must make the ghost: the paper's tracker ends beside the target.
                if mode == TrackerMode::Paper && off_frames > FRAMES / 2 {
                    ghosts += 1;
                }
                assert!(
                    longest <= MAX_SILENT_FRAMES,
                    "{name}: `tracking` for {longest} frames in a row while off the target \
                     (to frame {end})"
                );
            }
        }
    }
    assert!(
        ghosts >= 4,
        "the paper's tracker was expected to be left beside the target in most runs ({ghosts} of 8)"
    );
}

#[test]
fn the_paper_modes_status_does_not_feed_back_into_its_estimates() {
    // The target shrinks by 0.03 of its nominal size a frame for 20 frames, then vanishes for
    // 50 frames (board and paint the background's grey) and comes back where it was. While it
    // is gone the motion models extrapolate the shrinking scale through zero, and the window
    // goes where the target was last measured. Run once with a loss declared after 0.2 s and
    // once after 100 s: the statuses differ; the estimates, measurements and predictions (the
    // paper's, stages 1–7) must not. (They did when the window went to the last estimate
    // made before a reported loss.) Both find the target when it comes back.
    let truth: Vec<Location> = (0..100)
        .map(|k| Location::new(128.0, 112.0, 1.2 - 0.03 * k.min(20) as f64))
        .collect();
    let scenes: Vec<SynthScene> = (0..truth.len())
        .map(|k| {
            let hidden = (20..70).contains(&k);
            SynthScene {
                noise_sigma: 2.0,
                board: if hidden { 110.0 } else { 210.0 },
                paint: if hidden { 110.0 } else { 35.0 },
                ..SynthScene::default()
            }
        })
        .collect();
    let with = |lost_after_s| {
        run(
            TrackerConfig {
                lost_after_s,
                ..TrackerConfig::default()
            },
            &truth,
            &scenes,
            1,
        )
    };
    let (quick, patient) = (with(0.2), with(100.0));
    assert!(
        quick
            .iter()
            .zip(&patient)
            .any(|(a, b)| a.status != b.status),
        "the two runs were meant to report differently"
    );
    assert!(
        quick.iter().any(|o| !o.predicted.is_valid()),
        "the prediction was meant to leave the valid locations"
    );
    for (k, (a, b)) in quick.iter().zip(&patient).enumerate() {
        assert_eq!(a.estimate, b.estimate, "frame {k}");
        assert_eq!(a.measurement, b.measurement, "frame {k}");
        assert_eq!(a.next, b.next, "frame {k}");
    }
    let back = quick[70..]
        .iter()
        .position(|o| o.status == Status::Tracking)
        .expect("the target was not found again");
    assert!(back <= 2, "found again {back} frames after it came back");
    let e = quick[99].estimate;
    assert!(
        (e.c_x - 128.0).hypot(e.c_y - 112.0) < 1.0 && (e.scale / 0.6 - 1.0).abs() < 0.03,
        "{e:?}"
    );
}
