//! Dim, noisy frames (issue 37): both modes must hold the dim-weave sequence of
//! `tracker::synth` (`SequenceKind::DimWeave`: board and darkest paint 30 grey levels apart,
//! 0.42 and 0.30 of full scale, on a vehicle body of 0.34, over a photographic-like
//! background at 40 % contrast; blur σ = 0.9 px, then noise σ = 7; the target weaving
//! ±28 px over 90 frames, its scale 1.05 ± 0.2) for 180 frames at λ = 0.5 and 0.8: no frame
//! lost by the truth or reported lost, and the scale within [`SCALE_BOUND`].
//!
//! Why the paper's mode ran away here, where an independent implementation of 2.3–2.8 did
//! not: the threshold's scale. The paper thresholds eq. 4's mag = |∇f| at "8 in a grey level
//! range of 0 to 255" (2.3). This project read that as a step's height (the Sobel response
//! over 4), which passes steps of 8 grey levels, where |∇f| (the Sobel response over 8, the
//! derivative it estimates) passes steps of 16. With noise σ = 7 the step reading lets about
//! 40 % of pure-noise pixels through before suppression, |∇f| 3 %. Association then takes
//! the noise points within ζ of every prediction, each feature's measurement leans towards
//! its prediction, and the motion model's extrapolation carries the scale away. The tracker
//! now reads |∇f| (`TrackerConfig::edge_threshold`), and the paper's mode holds every run;
//! the step reading (`edge_threshold = 4` on |∇f|) is kept here to show the cause, and that
//! even then the runaway is never reported as `tracking`.
//!
//! A target 28 px wide (18 m away with the default camera, beyond the paper's 5–15 m) must
//! be held, or reported as not `tracking` while its scale is off by more than 20 % (for
//! more than [`MAX_WILD_RUN`] frames in a row).
//!
//! Run with `cargo test -p tracker --release --test dim_weave -- --nocapture` (the figures
//! go to stderr).

use tracker::synth::{dim_weave_scene, draw, nist_ten_segment, sequence, SequenceKind};
use tracker::{Camera, GrayView, Location, Status, Tracker, TrackerConfig, TrackerMode};

/// Frames of every sequence: 12 s at 15 Hz, two periods of the weave.
const FRAMES: usize = 180;
/// Noise seeds (and backgrounds) per mode and λ.
const SEEDS: u64 = 3;
/// The largest scale error allowed on the dim weave, as a fraction: measured at most 4.7 %
/// in the paper's mode and 5.9 % in robust mode over these seeds and both λ.
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

/// Runs a tracker in `mode` at `lambda` (and `edge_threshold`, when given) over `truth`,
/// frame k drawn with `scene(k)`.
fn run(
    mode: TrackerMode,
    lambda: f64,
    edge_threshold: Option<f64>,
    truth: &[Location],
    scene: impl Fn(usize) -> tracker::synth::SynthScene,
    seed: u64,
) -> Vec<Frame> {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let width_px = 2.0 * half_extent(&camera)[0];
    let mut config = TrackerConfig {
        mode,
        lambda,
        ..TrackerConfig::default()
    };
    if let Some(t) = edge_threshold {
        config.edge_threshold = t;
    }
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

/// The most frames in a row that a single wild estimate may be reported as `tracking` on
/// the 28 px target: 0.2 s, what the chase's range filters gate out.
const MAX_WILD_RUN: usize = 3;

/// The longest run of consecutive frame numbers in sorted `frames`.
fn longest_run(frames: &[usize]) -> usize {
    let mut longest = 0;
    let mut run = 0;
    for (i, &k) in frames.iter().enumerate() {
        run = if i > 0 && frames[i - 1] + 1 == k {
            run + 1
        } else {
            1
        };
        longest = longest.max(run);
    }
    longest
}

fn max(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, f64::max)
}

/// The dim-weave sequence of `seed` (from the image centre at scale 1), run as [`run`] does.
fn run_dim_weave(
    mode: TrackerMode,
    lambda: f64,
    edge_threshold: Option<f64>,
    seed: u64,
) -> Vec<Frame> {
    let start = Location::new(128.0, 112.0, 1.0);
    let half = half_extent(&Camera::default());
    let seq = sequence(SequenceKind::DimWeave, start, FRAMES, half, seed);
    run(
        mode,
        lambda,
        edge_threshold,
        &seq.truth,
        |k| seq.scenes[k].clone(),
        seed,
    )
}

/// The paper's 8 read as a step's height: |∇f| of 4.
const STEP_READING: f64 = 4.0;

#[test]
fn the_dim_weave_is_held_in_both_modes() {
    for mode in [TrackerMode::Paper, TrackerMode::Robust] {
        for lambda in [0.5, 0.8] {
            for seed in 1..=SEEDS {
                let frames = run_dim_weave(mode, lambda, None, seed);
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
fn read_as_a_steps_height_the_paper_threshold_runs_away_but_never_as_tracking() {
    let mut lost_runs = 0;
    for lambda in [0.5, 0.8] {
        for seed in 1..=SEEDS {
            let frames = run_dim_weave(TrackerMode::Paper, lambda, Some(STEP_READING), seed);
            let name = format!("paper λ = {lambda} seed {seed}");
            let lost = frames.iter().filter(|f| f.lost_truth).count();
            lost_runs += usize::from(lost > 0);
            let wild: Vec<usize> = (0..frames.len())
                .filter(|&k| {
                    frames[k].status == Status::Tracking && frames[k].scale_error.abs() > 0.2
                })
                .collect();
            let silent = frames
                .iter()
                .filter(|f| f.lost_truth && f.status == Status::Tracking)
                .count();
            eprintln!(
                "step reading, {name}: {lost} frames lost, {silent} of them reported \
                 tracking; worst scale error {:.1} %",
                100.0 * max(frames.iter().map(|f| f.scale_error.abs()))
            );
            assert!(
                wild.is_empty(),
                "{name}: `tracking` with the scale more than 20 % off at frames {wild:?}"
            );
            assert!(
                silent <= 15,
                "{name}: {silent} lost frames reported tracking"
            );
        }
    }
    eprintln!(
        "step reading: {lost_runs} of {} runs lost the target",
        2 * SEEDS
    );
    // The cause: at the step reading the scale runs away (measured: 5 runs of 6).
    assert!(lost_runs >= 1, "the step reading held every run");
}

#[test]
fn a_28_px_target_is_held_or_reported_as_not_tracking() {
    // The dim weave's scene, with the darkest paint 60 grey levels below the board (its
    // mid-tone edges 30), noise σ = 7, and the target 28 px wide (scale 0.547: 18 m away),
    // weaving ±15 px with its scale ±3 %. Measured (seeds 1–3, both λ): both modes held all
    // six runs, with worst scale errors of 3.8 % (paper) and 4.4 % (robust). (Reading the
    // paper's threshold as a step's height, the paper's mode lost one run of six and said
    // `tracking` on 3 frames whose scale was 20–29 % off, at most 2 in a row.)
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
                let frames = run(mode, lambda, None, &truth, scene, seed);
                let name = format!("{} λ = {lambda} seed {seed}", mode.as_str());
                let wild: Vec<usize> = (0..frames.len())
                    .filter(|&k| {
                        frames[k].status == Status::Tracking && frames[k].scale_error.abs() > 0.2
                    })
                    .collect();
                let longest_wild = longest_run(&wild);
                let lost = frames.iter().filter(|f| f.lost_truth).count();
                let silent = frames
                    .iter()
                    .filter(|f| f.lost_truth && f.status == Status::Tracking)
                    .count();
                eprintln!(
                    "28 px, {name}: {lost} frames lost ({silent} reported tracking), worst \
                     scale error {:.1} %, `tracking` more than 20 % off on {} frames ({} in a \
                     row)",
                    100.0 * max(frames.iter().map(|f| f.scale_error.abs())),
                    wild.len(),
                    longest_wild
                );
                // What would steer the car: a wild range reported as tracking for longer
                // than the chase's range filters gate out (a few frames), or a silent loss.
                assert!(
                    longest_wild <= MAX_WILD_RUN,
                    "{name}: `tracking` with the scale more than 20 % off at frames {wild:?}"
                );
                assert!(
                    silent <= 15,
                    "{name}: {silent} lost frames reported tracking"
                );
            }
        }
    }
}
