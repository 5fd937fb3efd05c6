//! Synthetic frames of the target (feature `synth`): for tests, benchmarks and
//! demonstrations, never for the tracker itself.
//!
//! The target is painted by the rule of [`crate::paint`], shared with the renderer. Pixels are area-sampled exactly (pixel (i, j) covers
//! [i − ½, i + ½] × [j − ½, j + ½]), so edges fall where the geometry says, to a fraction of a
//! pixel.

use crate::camera::Camera;
use crate::location::Location;
use crate::model::TargetModel;
use crate::paint::{self, Paint};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// The shipped target, `scenarios/targets/nist-ten-segment.toml`, built in code for tests,
/// benchmarks and demonstrations that read no files (a test in `sim` checks the two agree):
/// an outer frame 1.6 × 1.0 m, an inner frame 0.8 × 0.5 m, and two bars on the centre line
/// joining them; nominal range 10 m.
pub fn nist_ten_segment() -> TargetModel {
    TargetModel::new(
        "nist-ten-segment",
        10.0,
        vec![
            [-0.8, 0.5],
            [0.8, 0.5],
            [0.8, -0.5],
            [-0.8, -0.5],
            [-0.4, 0.25],
            [0.4, 0.25],
            [0.4, -0.25],
            [-0.4, -0.25],
            [0.0, 0.5],
            [0.0, 0.25],
            [0.0, -0.25],
            [0.0, -0.5],
        ],
        vec![
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 4],
            [8, 9],
            [10, 11],
        ],
    )
    .expect("the built-in model is valid")
}

/// An axis-aligned rectangle in image pixels, `[x0, y0, x1, y1]`, painted with a grey level
/// (or, for shadows, a multiplier).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left, top, right, bottom, pixels (continuous coordinates).
    pub bounds: [f64; 4],
    /// Grey level for paint; multiplier for a shadow.
    pub value: f64,
}

/// What a synthetic frame shows besides the target.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthScene {
    /// Frame width, pixels.
    pub width: usize,
    /// Frame height, pixels.
    pub height: usize,
    /// Background grey level.
    pub background: f64,
    /// Board grey level.
    pub board: f64,
    /// Grey level of the target's darkest paint (tone 0 of [`crate::paint::PaintRect`]).
    pub paint: f64,
    /// Gaussian sensor noise, grey levels (standard deviation).
    pub noise_sigma: f64,
    /// Distractors painted after the target (poles, wires, building edges): drawn on top.
    pub distractors: Vec<Rect>,
    /// Shadows: every pixel inside is multiplied by the rect's value (soft-edged by area).
    pub shadows: Vec<Rect>,
}

impl Default for SynthScene {
    /// A 256×242 frame (paper section 3), mid-grey background, no clutter, no noise.
    fn default() -> Self {
        SynthScene {
            width: 256,
            height: 242,
            background: 110.0,
            board: 210.0,
            paint: 35.0,
            noise_sigma: 0.0,
            distractors: Vec::new(),
            shadows: Vec::new(),
        }
    }
}

/// The target's painted rectangles in image pixels for a location: the board first, then
/// what [`crate::paint::layout`] paints on it (a model that cannot be painted with steps is
/// painted with stripes), each with its grey level between `scene.paint` (tone 0) and
/// `scene.board` (tone 1).
pub fn target_rects(
    model: &TargetModel,
    camera: &Camera,
    at: Location,
    scene: &SynthScene,
) -> Vec<Rect> {
    let [fx, fy] = camera.focal_px();
    let kx = at.scale * fx / model.nominal_range_m();
    let ky = at.scale * fy / model.nominal_range_m();
    let rects = paint::layout(model).unwrap_or_else(|_| paint::stripes(model));
    rects
        .iter()
        .map(|r| {
            let [x0, y0, x1, y1] = r.bounds_m;
            Rect {
                // Model y is up, image y is down.
                bounds: [
                    at.c_x + x0 * kx,
                    at.c_y - y1 * ky,
                    at.c_x + x1 * kx,
                    at.c_y - y0 * ky,
                ],
                value: scene.paint + r.tone * (scene.board - scene.paint),
            }
        })
        .collect()
}

/// Fraction of pixel (i, j) covered by a rectangle.
fn coverage(bounds: [f64; 4], i: usize, j: usize) -> f64 {
    let (px, py) = (i as f64, j as f64);
    let ox = (bounds[2].min(px + 0.5) - bounds[0].max(px - 0.5)).max(0.0);
    let oy = (bounds[3].min(py + 0.5) - bounds[1].max(py - 0.5)).max(0.0);
    ox * oy
}

/// Calls `f(index, coverage)` for every pixel of a `width × height` row-major buffer that
/// `rect` covers in part.
fn for_covered(width: usize, height: usize, rect: Rect, mut f: impl FnMut(usize, f64)) {
    let [x0, y0, x1, y1] = rect.bounds;
    let i0 = (x0 - 0.5).floor().max(0.0) as usize;
    let j0 = (y0 - 0.5).floor().max(0.0) as usize;
    let i1 = ((x1 + 0.5).ceil().max(0.0) as usize).min(width);
    let j1 = ((y1 + 0.5).ceil().max(0.0) as usize).min(height);
    for j in j0..j1 {
        for i in i0..i1 {
            let c = coverage(rect.bounds, i, j);
            if c > 0.0 {
                f(j * width + i, c);
            }
        }
    }
}

/// Paints a rectangle over `buf` (row-major f64 grey levels), mixing by coverage.
fn paint(buf: &mut [f64], width: usize, height: usize, rect: Rect, multiply: bool) {
    for_covered(width, height, rect, |k, c| {
        let p = &mut buf[k];
        let target = if multiply {
            *p * rect.value
        } else {
            rect.value
        };
        *p += c * (target - *p);
    });
}

/// Adds a rectangle lying wholly on a surface of level `under`: each pixel gains its covered
/// share of `rect.value − under`.
fn add_over(buf: &mut [f64], width: usize, height: usize, rect: Rect, under: f64) {
    for_covered(width, height, rect, |k, c| {
        buf[k] += c * (rect.value - under)
    });
}

/// Draws one frame: background, the target at `at`, distractors, shadows, then noise from
/// `seed`. Returns row-major grey levels, `scene.width × scene.height`.
pub fn draw(
    model: &TargetModel,
    camera: &Camera,
    at: Location,
    scene: &SynthScene,
    seed: u64,
) -> Vec<u8> {
    let (w, h) = (scene.width, scene.height);
    let mut buf = vec![scene.background; w * h];
    let rects = target_rects(model, camera, at, scene);
    let steps = model.paint() == Paint::Steps && paint::layout(model).is_ok();
    for (k, &rect) in rects.iter().enumerate() {
        if steps && k > 0 {
            // Step regions tile the board without overlapping: adding each one's share of a
            // pixel over the board's level mixes the regions exactly by area.
            add_over(&mut buf, w, h, rect, scene.board);
        } else {
            paint(&mut buf, w, h, rect, false);
        }
    }
    for &rect in &scene.distractors {
        paint(&mut buf, w, h, rect, false);
    }
    for &rect in &scene.shadows {
        paint(&mut buf, w, h, rect, true);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let noise = Normal::new(0.0, scene.noise_sigma.max(0.0)).expect("finite sigma");
    buf.iter()
        .map(|&v| {
            let n = if scene.noise_sigma > 0.0 {
                noise.sample(&mut rng)
            } else {
                0.0
            };
            // Round half away from zero, clamp to the 8-bit range.
            (v + n).round().clamp(0.0, 255.0) as u8
        })
        .collect()
}

/// The frame the benchmark and the profiling example measure: the shipped target at scale 1
/// near the image centre, with sensor noise (σ = 3), a pole and a shadow band, so that
/// association has clutter to reject. Returns the location drawn and the pixels (256×242).
pub fn benchmark_frame(model: &TargetModel, camera: &Camera) -> (Location, Vec<u8>) {
    let at = Location::new(128.0, 112.0, 1.0);
    let scene = SynthScene {
        noise_sigma: 3.0,
        distractors: vec![Rect {
            bounds: [90.0, 0.0, 93.0, 242.0],
            value: 60.0,
        }],
        shadows: vec![Rect {
            bounds: [120.0, 0.0, 135.0, 242.0],
            value: 0.6,
        }],
        ..SynthScene::default()
    };
    (at, draw(model, camera, at, &scene, 1))
}

/// A smooth pseudo-random walk of the target for test sequences: `frames` locations around
/// `start`, moving by up to `px_per_frame` pixels and `scale_per_frame` per frame.
pub fn wander(
    start: Location,
    frames: usize,
    px_per_frame: f64,
    scale_per_frame: f64,
    seed: u64,
) -> Vec<Location> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut v = [0.0f64; 3];
    let mut at = start;
    let mut out = Vec::with_capacity(frames);
    for _ in 0..frames {
        out.push(at);
        // Velocities drift smoothly (a second-order motion, like the model's).
        for (k, limit) in [px_per_frame, px_per_frame, scale_per_frame]
            .into_iter()
            .enumerate()
        {
            v[k] = (v[k] + rng.random_range(-0.3..0.3) * limit).clamp(-limit, limit);
        }
        at.c_x += v[0];
        at.c_y += v[1];
        at.scale = (at.scale + v[2]).max(0.2);
    }
    out
}

/// The kinds of synthetic sequence `carfollow synth` writes and the tests run, each a
/// condition the paper's section 4 or a real road brings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SequenceKind {
    /// The smooth wander of [`wander`], on a plain background.
    Plain,
    /// The wander with noise, a pole and a wire near the target and a shadow band sweeping
    /// across it.
    Clutter,
    /// Abrupt sideways swerves: 24 px in 4 frames, every 40 frames, alternating in
    /// direction, on top of a gentle wander.
    Swerve,
    /// Camera shake on a rough road: ±5 px vertically at 2.3 Hz and ±2 px sideways at
    /// 1.7 Hz (at 15 frames a second), on top of a gentle wander.
    Shake,
    /// A dim, noisy scene: noise σ = 7, and 30 grey levels of contrast across the weakest of
    /// the target's edges (the board 80, the darkest paint 20: the step-painted target's
    /// mid tone, 50, is 30 levels from both).
    Dim,
}

impl SequenceKind {
    /// Every kind, in order.
    pub const ALL: [SequenceKind; 5] = [
        SequenceKind::Plain,
        SequenceKind::Clutter,
        SequenceKind::Swerve,
        SequenceKind::Shake,
        SequenceKind::Dim,
    ];

    /// Lower-case name.
    pub fn as_str(self) -> &'static str {
        match self {
            SequenceKind::Plain => "plain",
            SequenceKind::Clutter => "clutter",
            SequenceKind::Swerve => "swerve",
            SequenceKind::Shake => "shake",
            SequenceKind::Dim => "dim",
        }
    }

    /// Parses a name of [`SequenceKind::as_str`].
    pub fn parse(text: &str) -> Option<SequenceKind> {
        SequenceKind::ALL.into_iter().find(|k| k.as_str() == text)
    }
}

/// A synthetic sequence: where the target is in each frame, and what else each frame shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Sequence {
    /// The target's true location, frame by frame.
    pub truth: Vec<Location>,
    /// Each frame's scene.
    pub scenes: Vec<SynthScene>,
}

/// A sequence of `kind`, `frames` long, from `start`, seeded. `half_extent_px` is half the
/// target's size in pixels at scale 1 (for placing clutter beside it).
pub fn sequence(
    kind: SequenceKind,
    start: Location,
    frames: usize,
    half_extent_px: [f64; 2],
    seed: u64,
) -> Sequence {
    let gentle = |px: f64| wander(start, frames, px, 0.004, seed);
    let truth: Vec<Location> = match kind {
        SequenceKind::Plain | SequenceKind::Clutter | SequenceKind::Dim => {
            wander(start, frames, 1.5, 0.01, seed)
        }
        SequenceKind::Swerve => gentle(0.5)
            .into_iter()
            .enumerate()
            .map(|(k, mut at)| {
                // Swerves start at frames 20, 60, 100, ...: right, back left, right, ...
                let mut offset = 0.0;
                let mut sign = 1.0;
                let mut s = 20usize;
                while s <= k {
                    let progress = ((k - s) as f64 / 4.0).min(1.0);
                    offset += sign * 24.0 * progress;
                    sign = -sign;
                    s += 40;
                }
                at.c_x += offset;
                at
            })
            .collect(),
        SequenceKind::Shake => gentle(0.5)
            .into_iter()
            .enumerate()
            .map(|(k, mut at)| {
                let t = k as f64 / 15.0;
                at.c_y += 5.0 * (std::f64::consts::TAU * 2.3 * t).sin();
                at.c_x += 2.0 * (std::f64::consts::TAU * 1.7 * t + 0.7).sin();
                at
            })
            .collect(),
    };
    sequence_with_truth(kind, truth, half_extent_px)
}

/// The cluttered scene of frame `k` with the target at `at` (`half_extent_px`: half its size
/// at scale 1): noise σ = 4, a telephone pole 7 px outside the board's left edge and a wire
/// 9 px above it, near and parallel to features, and a shadow band sweeping across the
/// target.
pub fn clutter_scene(k: usize, at: Location, half_extent_px: [f64; 2]) -> SynthScene {
    let (hw, hh) = (half_extent_px[0] * at.scale, half_extent_px[1] * at.scale);
    let sweep = at.c_x - 60.0 + (2.0 * k as f64) % 120.0;
    SynthScene {
        noise_sigma: 4.0,
        distractors: vec![
            Rect {
                bounds: [at.c_x - hw - 12.0, 0.0, at.c_x - hw - 9.0, 242.0],
                value: 60.0,
            },
            Rect {
                bounds: [0.0, at.c_y - hh - 13.0, 256.0, at.c_y - hh - 12.0],
                value: 70.0,
            },
        ],
        shadows: vec![Rect {
            bounds: [sweep, 0.0, sweep + 14.0, 242.0],
            value: 0.55,
        }],
        ..SynthScene::default()
    }
}

/// The scenes of a sequence of `kind` for a given truth (see [`sequence`]).
pub fn sequence_with_truth(
    kind: SequenceKind,
    truth: Vec<Location>,
    half_extent_px: [f64; 2],
) -> Sequence {
    let scenes = truth
        .iter()
        .enumerate()
        .map(|(k, at)| match kind {
            SequenceKind::Clutter => clutter_scene(k, *at, half_extent_px),
            SequenceKind::Dim => SynthScene {
                background: 55.0,
                board: 80.0,
                paint: 20.0,
                noise_sigma: 7.0,
                ..SynthScene::default()
            },
            SequenceKind::Swerve | SequenceKind::Shake => SynthScene {
                noise_sigma: 2.0,
                ..SynthScene::default()
            },
            SequenceKind::Plain => SynthScene::default(),
        })
        .collect();
    Sequence { truth, scenes }
}

/// How a tracker did on a synthetic sequence, judged against its truth as the closed loop
/// judges it: a frame is lost when the estimate is off by more than a quarter of the
/// target's width, or its scale by more than 25 %.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SequenceScore {
    /// Frames.
    pub frames: usize,
    /// Frames lost by the truth.
    pub lost_truth: usize,
    /// Frames lost by the truth while the tracker said `tracking`.
    pub silent: usize,
    /// The longest run of such frames at the start of a loss: how many frames after the
    /// truth lost the target the tracker still said `tracking`.
    pub longest_silence: usize,
    /// Frames the tracker said `tracking`.
    pub tracking: usize,
    /// Mean centre error over the frames not lost by the truth, pixels.
    pub mean_error_px: f64,
    /// The first frame the tracker said `tracking` (0 when started on the target).
    pub first_tracking: Option<usize>,
    /// Frames on which a search ran.
    pub searched: usize,
}

/// Runs `tracker` over `seq` (frame k at k / 15 s) and scores it. With the environment
/// variable `SYNTH_TRACE` set, each frame's truth, estimate, status and check go to stderr
/// (the `trace` example uses it).
pub fn score_sequence(
    tracker: &mut crate::Tracker,
    model: &TargetModel,
    camera: &Camera,
    seq: &Sequence,
    seed: u64,
) -> SequenceScore {
    let width_px = model.size_m()[0] * camera.focal_px()[0] / model.nominal_range_m();
    let mut s = SequenceScore {
        frames: seq.truth.len(),
        ..SequenceScore::default()
    };
    let trace = std::env::var_os("SYNTH_TRACE").is_some();
    let (mut err_sum, mut err_n) = (0.0, 0usize);
    // Within a loss event: whether the tracker has said so yet, and how long it has not.
    let (mut reported, mut run) = (false, 0usize);
    for (k, (at, scene)) in seq.truth.iter().zip(&seq.scenes).enumerate() {
        let px = draw(
            model,
            camera,
            *at,
            scene,
            seed.wrapping_mul(1_000_003) + k as u64,
        );
        let view = crate::GrayView::new(scene.width, scene.height, &px).expect("sized frame");
        let out = tracker.step(view, k as f64 / 15.0);
        let e = out.estimate;
        let err = (e.c_x - at.c_x).hypot(e.c_y - at.c_y);
        let lost = err > 0.25 * width_px * at.scale || (e.scale / at.scale - 1.0).abs() > 0.25;
        let tracking = out.status == crate::Status::Tracking;
        if tracking {
            s.tracking += 1;
            s.first_tracking.get_or_insert(k);
        }
        s.searched += usize::from(out.searched);
        if trace {
            eprintln!(
                "{k:4} truth {:7.2} {:7.2} {:.3}  est {:7.2} {:7.2} {:.3}  pred {:7.2} {:7.2}  {:8} cov {:.2} {:.2} gain {:.2} thr {:.1}{}{}",
                at.c_x, at.c_y, at.scale, e.c_x, e.c_y, e.scale, out.predicted.c_x,
                out.predicted.c_y, out.status.as_str(), out.coverage[0], out.coverage[1], out.coverage_gain,
                out.edge_threshold, if out.searched { " searched" } else { "" },
                if lost { " LOST" } else { "" }
            );
        }
        if lost {
            s.lost_truth += 1;
            if tracking {
                s.silent += 1;
            }
            if !reported {
                if tracking {
                    run += 1;
                    s.longest_silence = s.longest_silence.max(run);
                } else {
                    reported = true;
                }
            }
        } else {
            (reported, run) = (false, 0);
            err_sum += err;
            err_n += 1;
        }
    }
    s.mean_error_px = if err_n > 0 {
        err_sum / err_n as f64
    } else {
        f64::NAN
    };
    s
}
