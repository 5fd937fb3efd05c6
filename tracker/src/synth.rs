//! Synthetic frames of the target (feature `synth`): for tests, benchmarks and
//! demonstrations, never for the tracker itself.
//!
//! The target is painted by the rule of [`crate::paint`], shared with the renderer. Pixels are area-sampled exactly (pixel (i, j) covers
//! [i − ½, i + ½] × [j − ½, j + ½]), so edges fall where the geometry says, to a fraction of a
//! pixel.

use crate::camera::Camera;
use crate::location::Location;
use crate::model::TargetModel;
use crate::paint::{BOARD_MARGIN_M, STRIPE_EXTENSION_M, STRIPE_WIDTH_M};
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
    /// Stripe grey level.
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

/// The target's painted rectangles (board first, then stripes) in image pixels, for a
/// location.
pub fn target_rects(
    model: &TargetModel,
    camera: &Camera,
    at: Location,
    scene: &SynthScene,
) -> Vec<Rect> {
    let [fx, fy] = camera.focal_px();
    let kx = at.scale * fx / model.nominal_range_m();
    let ky = at.scale * fy / model.nominal_range_m();
    let to_px = |x0: f64, y0: f64, x1: f64, y1: f64, value: f64| Rect {
        // Model y is up, image y is down.
        bounds: [
            at.c_x + x0 * kx,
            at.c_y - y1 * ky,
            at.c_x + x1 * kx,
            at.c_y - y0 * ky,
        ],
        value,
    };
    let corners = model.corners_m();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &[x, y] in corners {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let m = BOARD_MARGIN_M;
    let mut rects = vec![to_px(x0 - m, y0 - m, x1 + m, y1 + m, scene.board)];
    let (hw, ext) = (0.5 * STRIPE_WIDTH_M, STRIPE_EXTENSION_M);
    for &[a, b] in model.segments() {
        let [ax, ay] = corners[a];
        let [bx, by] = corners[b];
        let (lx, hx) = (ax.min(bx), ax.max(bx));
        let (ly, hy) = (ay.min(by), ay.max(by));
        let rect = if (ay - by).abs() < 1e-9 {
            to_px(lx - ext, ay - hw, hx + ext, ay + hw, scene.paint)
        } else {
            to_px(ax - hw, ly - ext, ax + hw, hy + ext, scene.paint)
        };
        rects.push(rect);
    }
    rects
}

/// Fraction of pixel (i, j) covered by a rectangle.
fn coverage(bounds: [f64; 4], i: usize, j: usize) -> f64 {
    let (px, py) = (i as f64, j as f64);
    let ox = (bounds[2].min(px + 0.5) - bounds[0].max(px - 0.5)).max(0.0);
    let oy = (bounds[3].min(py + 0.5) - bounds[1].max(py - 0.5)).max(0.0);
    ox * oy
}

/// Paints a rectangle over `buf` (row-major f64 grey levels), mixing by coverage.
fn paint(buf: &mut [f64], width: usize, height: usize, rect: Rect, multiply: bool) {
    let [x0, y0, x1, y1] = rect.bounds;
    let i0 = (x0 - 0.5).floor().max(0.0) as usize;
    let j0 = (y0 - 0.5).floor().max(0.0) as usize;
    let i1 = ((x1 + 0.5).ceil().max(0.0) as usize).min(width);
    let j1 = ((y1 + 0.5).ceil().max(0.0) as usize).min(height);
    for j in j0..j1 {
        for i in i0..i1 {
            let c = coverage(rect.bounds, i, j);
            if c > 0.0 {
                let p = &mut buf[j * width + i];
                let target = if multiply {
                    *p * rect.value
                } else {
                    rect.value
                };
                *p += c * (target - *p);
            }
        }
    }
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
    for rect in target_rects(model, camera, at, scene) {
        paint(&mut buf, w, h, rect, false);
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
