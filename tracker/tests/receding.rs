//! A target receding beyond the tracker's resolution (at 90 km/h with the 8 mm lens the
//! target 25–40 m ahead). Its competing parallel features come closer in the image than
//! stage 1 separates (`tracker::resolvability::EDGE_SEPARATION_PX`), where association (2.4)
//! can no longer tell them apart, and an estimate reported as `tracking` there would steer a
//! car with a wild range. Both modes must say so instead: no frame reported `tracking` while
//! its estimate is off by the closed loop's tolerance, an `unresolved` event as the features
//! come within the limit, and the target reported `tracking` while well resolved.
//!
//! Run with `cargo test -p tracker --release --test receding -- --nocapture` (the figures
//! go to stderr).

use tracker::resolvability::{confusable_spacing, EDGE_SEPARATION_PX};
use tracker::synth::{draw, nist_ten_segment, Body, SynthScene, Texture};
use tracker::{
    Camera, GrayView, Location, Status, TrackEvent, Tracker, TrackerConfig, TrackerMode,
};

/// Frames of every run: 10 s at 15 Hz.
const FRAMES: usize = 150;
/// The scale at the first and the last frame: 13 m to 40 m with the default camera, the
/// features' smallest spacing going from 6.2 px to 2.0 px.
const SCALES: (f64, f64) = (0.77, 0.25);
const SEEDS: u64 = 3;
/// "Well resolved", pixels: the spacing from which every frame must be `tracking`.
const WELL_RESOLVED_PX: f64 = 4.5;

/// The truth: the scale shrinking geometrically, the centre drifting gently.
fn truth() -> Vec<Location> {
    let (a, b) = SCALES;
    let tau = std::f64::consts::TAU;
    (0..FRAMES)
        .map(|k| {
            let f = k as f64 / (FRAMES - 1) as f64;
            Location::new(
                128.0 + 6.0 * (tau * f).sin(),
                115.0 + 2.0 * (tau * 1.5 * f).sin(),
                a * (b / a).powf(f),
            )
        })
        .collect()
}

/// The two scenes: the board alone on a flat background, and the board on a dark vehicle
/// body over a textured background; both with a little blur and sensor noise.
fn scenes(seed: u64) -> [(&'static str, SynthScene); 2] {
    let plain = SynthScene {
        noise_sigma: 2.0,
        blur_sigma: 0.6,
        ..SynthScene::default()
    };
    let on_body = SynthScene {
        background: 100.0,
        board: 200.0,
        paint: 40.0,
        texture: Some(Texture {
            seed,
            contrast: 0.3,
        }),
        body: Some(Body {
            bounds_m: [-1.3, -1.4, 1.3, 1.05],
            value: 80.0,
        }),
        ..plain.clone()
    };
    [("plain", plain), ("on a body", on_body)]
}

#[test]
fn a_target_receding_beyond_resolution_is_reported_not_tracked() {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let truth = truth();
    for mode in [TrackerMode::Paper, TrackerMode::Robust] {
        for seed in 1..=SEEDS {
            for (scene_name, scene) in scenes(seed) {
                let config = TrackerConfig {
                    mode,
                    lambda: 0.8,
                    ..TrackerConfig::default()
                };
                let mut tracker = Tracker::new(model.clone(), camera, config, truth[0]).unwrap();
                let spacing_1 = {
                    let [x, y] = confusable_spacing(tracker.features());
                    x.min(y)
                };
                let width_1 = tracker.target_width_px();
                let limit = EDGE_SEPARATION_PX;
                let (mut wild, mut resolved, mut resolved_tracking) = (Vec::new(), 0, 0);
                let mut unresolved_at_px = None;
                for (k, at) in truth.iter().enumerate() {
                    let px = draw(&model, &camera, *at, &scene, seed * 1_000_003 + k as u64);
                    let o = tracker.step(
                        GrayView::new(scene.width, scene.height, &px).unwrap(),
                        k as f64 / 15.0,
                    );
                    let e = o.estimate;
                    let off = (e.c_x - at.c_x).hypot(e.c_y - at.c_y) > 0.25 * width_1 * at.scale
                        || (e.scale / at.scale - 1.0).abs() > 0.25;
                    let spacing = spacing_1 * at.scale;
                    if o.status == Status::Tracking && off {
                        wild.push(k);
                    }
                    if spacing >= WELL_RESOLVED_PX {
                        resolved += 1;
                        resolved_tracking += usize::from(o.status == Status::Tracking);
                    }
                    if o.event == Some(TrackEvent::Unresolved) && unresolved_at_px.is_none() {
                        unresolved_at_px = Some(spacing);
                    }
                }
                let name = format!("{} seed {seed} {scene_name}", mode.as_str());
                eprintln!(
                    "{name}: {} frames tracking while off; tracking {resolved_tracking} of \
                     {resolved} well-resolved frames; unresolved at a spacing of {:?} px",
                    wild.len(),
                    unresolved_at_px
                );
                assert!(wild.is_empty(), "{name}: tracking while off at {wild:?}");
                assert_eq!(
                    resolved_tracking, resolved,
                    "{name}: not tracking a well-resolved target"
                );
                let at = unresolved_at_px.unwrap_or_else(|| panic!("{name}: no `unresolved`"));
                assert!(
                    (0.85 * limit..=1.1 * limit).contains(&at),
                    "{name}: unresolved at a true spacing of {at:.2} px (ζ {limit})"
                );
            }
        }
    }
}
