//! Dim, noisy frames (issue 37): both modes must hold the dim-weave sequence of
//! `tracker::synth` (`SequenceKind::DimWeave`: board and darkest paint 30 grey levels apart,
//! 0.42 and 0.30 of full scale, on a vehicle body of 0.34, over a photographic-like
//! background at 40 % contrast; blur σ = 0.9 px, then noise σ = 7; the target weaving
//! ±28 px over 90 frames, its scale 1.05 ± 0.2) for 180 frames at λ = 0.5 and 0.8: no frame
//! lost by the truth or reported lost, and the scale within [`SCALE_BOUND`].
//!
//! The paper's mode failed this while its gradient read a step's height (the Sobel response
//! over 4, twice eq. 4's |∇f|), which halved the paper's threshold of 8 (2.3): about 40 %
//! of pure-noise pixels passed it instead of 3 %, association took the noise points within
//! ζ of every prediction, each measurement leaned towards its prediction, and the scale ran
//! away (seed 2, λ = 0.8: +5 % at frame 5, +16 % at 8, +30 % at 10, then lost for the rest
//! of the sequence; 5 of 6 runs lost it).
//!
//! A target 28 px wide (18 m away with the default camera, beyond the paper's 5–15 m) must
//! be held, or reported as not `tracking` while its scale is off by more than 20 %.
//!
//! Run with `cargo test -p tracker --release --test dim_weave -- --nocapture` (the figures
//! go to stderr).

use tracker::synth::{dim_weave_scene, draw, nist_ten_segment, sequence, SequenceKind};
use tracker::{Camera, GrayView, Location, Status, Tracker, TrackerConfig, TrackerMode};

/// Frames of every sequence: 12 s at 15 Hz, two periods of the weave.
const FRAMES: usize = 180;
/// Noise seeds (and backgrounds) per mode and λ.
const SEEDS: u64 = 3;
/// The largest scale error allowed on the dim weave, as a fraction: measured at most 4.9 %
/// in the paper's mode and 5.9 % in robust mode over these seeds and both λ (and 4.9 % in
/// the paper's mode over six seeds).
const SCALE_BOUND: f64 = 0.08;
/// The largest centre error allowed on the dim weave, pixels: measured at most 2.2 px.
const CENTRE_BOUND_PX: f64 = 3.5;

fn half_extent(camera: &Camera) -> [f64; 2] {
    let model = nist_ten_segment();
    model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m())
}

/// One frame's result against its truth.
struct Frame {
    status: Status,
    centre_error_px: f64,
    /// estimate / truth − 1.
    scale_error: f64,
    /// Off by more than a quarter of the target's width or 25 % in scale (the closed loop's
    /// definition of a lost frame, `synth::score_sequence`'s).
    lost_truth: bool,
}

/// Runs a tracker in `mode` at `lambda` over `truth`, frame k drawn with `scene(k)`.
fn run(
    mode: TrackerMode,
    lambda: f64,
    truth: &[Location],
    scene: impl Fn(usize) -> tracker::synth::SynthScene,
    seed: u64,
) -> Vec<Frame> {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let width_px = 2.0 * half_extent(&camera)[0];
    let config = TrackerConfig {
        mode,
        lambda,
        ..TrackerConfig::default()
    };
    let mut tracker = Tracker::new(model.clone(), camera, config, truth[0]).unwrap();
    truth
        .iter()
        .enumerate()
        .map(|(k, at)| {
            let s = scene(k);
            let px = draw(&model, &camera, *at, &s, seed * 1_000_003 + k as u64);
            let out = tracker.step(
                GrayView::new(s.width, s.height, &px).unwrap(),
                k as f64 / 15.0,
            );
            let e = out.estimate;
            let centre_error_px = (e.c_x - at.c_x).hypot(e.c_y - at.c_y);
            let scale_error = e.scale / at.scale - 1.0;
            Frame {
                status: out.status,
                centre_error_px,
                scale_error,
                lost_truth: centre_error_px > 0.25 * width_px * at.scale
                    || scale_error.abs() > 0.25,
            }
        })
        .collect()
}

fn max(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, f64::max)
}

#[test]
fn the_dim_weave_is_held_in_both_modes_at_both_lambdas() {
    let camera = Camera::default();
    let start = Location::new(128.0, 112.0, 1.0);
    for mode in [TrackerMode::Paper, TrackerMode::Robust] {
        for lambda in [0.5, 0.8] {
            for seed in 1..=SEEDS {
                let seq = sequence(
                    SequenceKind::DimWeave,
                    start,
                    FRAMES,
                    half_extent(&camera),
                    seed,
                );
                let frames = run(mode, lambda, &seq.truth, |k| seq.scenes[k].clone(), seed);
                let name = format!("{} λ = {lambda} seed {seed}", mode.as_str());
                let lost: Vec<usize> = (0..frames.len())
                    .filter(|&k| frames[k].lost_truth)
                    .collect();
                let reported_lost = frames.iter().filter(|f| f.status == Status::Lost).count();
                let tracking = frames
                    .iter()
                    .filter(|f| f.status == Status::Tracking)
                    .count();
                let worst_scale = max(frames.iter().map(|f| f.scale_error.abs()));
                let worst_centre = max(frames.iter().map(|f| f.centre_error_px));
                eprintln!(
                    "{name}: {} frames lost, {reported_lost} reported lost, {tracking} tracking; \
                     worst scale error {:.1} %, centre {worst_centre:.2} px",
                    lost.len(),
                    100.0 * worst_scale
                );
                assert!(lost.is_empty(), "{name}: frames lost {lost:?}");
                assert_eq!(reported_lost, 0, "{name}: reported lost");
                assert!(
                    worst_scale <= SCALE_BOUND,
                    "{name}: scale off by {:.1} %",
                    100.0 * worst_scale
                );
                assert!(
                    worst_centre <= CENTRE_BOUND_PX,
                    "{name}: centre off by {worst_centre:.2} px"
                );
                // The status follows the track: the mid-tone edges (15 grey levels) are below
                // the paper's threshold, so a fit on the target covers only about half its
                // outline and sometimes falls below the coverage check; still, most frames
                // are reported tracking.
                assert!(
                    tracking >= 4 * FRAMES / 5,
                    "{name}: tracking in only {tracking} of {FRAMES} frames"
                );
            }
        }
    }
}

#[test]
fn a_28_px_target_is_held_or_reported_as_not_tracking() {
    // The dim weave's scene, with the darkest paint 60 grey levels below the board (its
    // mid-tone edges 30), noise σ = 7, and the target 28 px wide (scale 0.547: 18 m away),
    // weaving ±15 px with its scale ±3 %. Measured: with the gradient read as a step's
    // height, the paper's mode lost 6 of 20 runs (seeds 1–10, both λ) and said `tracking`
    // on 18 frames whose scale was more than 20 % off; with eq. 4's gradient it held all 20
    // runs (worst scale error 6.9 %), and so did robust mode (6.0 %).
    let tau = std::f64::consts::TAU;
    let truth: Vec<Location> = (0..FRAMES)
        .map(|k| {
            let phase = tau * k as f64 / 90.0;
            Location::new(
                128.0 + 15.0 * phase.sin(),
                112.0 + 3.0 * (0.7 * phase).sin(),
                0.547 * (1.0 + 0.03 * (0.5 * phase).sin()),
            )
        })
        .collect();
    let width_px = 2.0 * half_extent(&Camera::default())[0] * truth[0].scale;
    assert!((width_px - 28.0).abs() < 0.1, "{width_px} px wide");
    for mode in [TrackerMode::Paper, TrackerMode::Robust] {
        for lambda in [0.5, 0.8] {
            for seed in 1..=SEEDS {
                let scene = |_| {
                    let mut s = dim_weave_scene(seed);
                    s.paint = s.board - 60.0;
                    s
                };
                let frames = run(mode, lambda, &truth, scene, seed);
                let name = format!("{} λ = {lambda} seed {seed}", mode.as_str());
                let wild: Vec<usize> = (0..frames.len())
                    .filter(|&k| {
                        frames[k].status == Status::Tracking && frames[k].scale_error.abs() > 0.2
                    })
                    .collect();
                let lost = frames.iter().filter(|f| f.lost_truth).count();
                eprintln!(
                    "28 px, {name}: {lost} frames lost, worst scale error {:.1} %",
                    100.0 * max(frames.iter().map(|f| f.scale_error.abs()))
                );
                assert!(
                    wild.is_empty(),
                    "{name}: `tracking` with the scale more than 20 % off at frames {wild:?}"
                );
            }
        }
    }
}
