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
    /// A photographic-like texture over the background (none: a flat `background`).
    pub texture: Option<Texture>,
    /// The lead vehicle's body around the board, moving with the target: painted over the
    /// background before the target (none: the board stands on the background).
    pub body: Option<Body>,
    /// Gaussian blur of the optics, standard deviation in pixels, applied to the drawn
    /// frame before the sensor noise (0: none).
    pub blur_sigma: f64,
}

/// A seeded photographic-like background: multi-octave value noise with the same amplitude
/// in every octave, from [`TEXTURE_COARSEST_PX`] down to 2 px. Equal energy per octave is a
/// 1/f amplitude spectrum, as natural images have (D. J. Field, "Relations between the
/// statistics of natural images and the response properties of cortical cells", JOSA A
/// 4(12), 1987).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texture {
    /// Seed of the lattice values.
    pub seed: u64,
    /// Michelson contrast, (max − min) / (max + min): the texture spans
    /// `background × (1 ± contrast)` over the frame.
    pub contrast: f64,
}

/// The wavelength of the texture's coarsest octave, pixels: a quarter of the frame's width.
pub const TEXTURE_COARSEST_PX: f64 = 64.0;

/// The lead vehicle's body: a rectangle in the target's frame (metres from the target's
/// centre, x right, y up, as [`crate::paint::PaintRect`]), with its grey level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// `[x0, y0, x1, y1]`, metres.
    pub bounds_m: [f64; 4],
    /// Grey level.
    pub value: f64,
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
            texture: None,
            body: None,
            blur_sigma: 0.0,
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
        .map(|r| Rect {
            bounds: image_bounds(r.bounds_m, at, [kx, ky]),
            value: scene.paint + r.tone * (scene.board - scene.paint),
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
    let mut buf = match scene.texture {
        Some(t) => cached_texture(w, h, scene.background, t),
        None => vec![scene.background; w * h],
    };
    if let Some(body) = scene.body {
        paint(&mut buf, w, h, body_rect(model, camera, at, body), false);
    }
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
    if scene.blur_sigma > 0.0 {
        blur(&mut buf, w, h, scene.blur_sigma);
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

/// A rectangle of the target's plane, `[x0, y0, x1, y1]` metres from its centre (y up), in
/// image pixels for the target at `at`, `k` pixels a metre (image y is down).
fn image_bounds([x0, y0, x1, y1]: [f64; 4], at: Location, [kx, ky]: [f64; 2]) -> [f64; 4] {
    [
        at.c_x + x0 * kx,
        at.c_y - y1 * ky,
        at.c_x + x1 * kx,
        at.c_y - y0 * ky,
    ]
}

/// The body's rectangle in image pixels for the target at `at`.
fn body_rect(model: &TargetModel, camera: &Camera, at: Location, body: Body) -> Rect {
    let [fx, fy] = camera.focal_px();
    let kx = at.scale * fx / model.nominal_range_m();
    let ky = at.scale * fy / model.nominal_range_m();
    Rect {
        bounds: image_bounds(body.bounds_m, at, [kx, ky]),
        value: body.value,
    }
}

/// A `width × height` frame of [`Texture`] about the grey level `mean`: value noise (random
/// lattice values, smoothly interpolated) summed over octaves from [`TEXTURE_COARSEST_PX`]
/// down to 2 px with equal amplitudes, then stretched so that its minimum and
/// maximum over the frame are `mean × (1 ∓ contrast)`.
pub fn texture(width: usize, height: usize, mean: f64, t: Texture) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(t.seed);
    let mut sum = vec![0.0; width * height];
    let mut wavelength = TEXTURE_COARSEST_PX;
    while wavelength >= 2.0 {
        let nx = (width as f64 / wavelength).ceil() as usize + 2;
        let ny = (height as f64 / wavelength).ceil() as usize + 2;
        let lattice: Vec<f64> = (0..nx * ny).map(|_| rng.random_range(-1.0..1.0)).collect();
        // Smoothstep interpolation between lattice values, each octave offset by a random
        // fraction of its cell so that no lattice line is common to all octaves.
        let (ox, oy) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
        for j in 0..height {
            let fy = j as f64 / wavelength + oy;
            let (cy, ty) = (fy.floor() as usize, fy.fract());
            let sy = ty * ty * (3.0 - 2.0 * ty);
            for i in 0..width {
                let fx = i as f64 / wavelength + ox;
                let (cx, tx) = (fx.floor() as usize, fx.fract());
                let sx = tx * tx * (3.0 - 2.0 * tx);
                let v = |a: usize, b: usize| lattice[(cy + b) * nx + cx + a];
                let top = v(0, 0) + sx * (v(1, 0) - v(0, 0));
                let bottom = v(0, 1) + sx * (v(1, 1) - v(0, 1));
                sum[j * width + i] += top + sy * (bottom - top);
            }
        }
        wavelength /= 2.0;
    }
    let (lo, hi) = sum
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let (mid, half) = (0.5 * (lo + hi), (0.5 * (hi - lo)).max(f64::MIN_POSITIVE));
    sum.iter()
        .map(|&v| mean * (1.0 + t.contrast * (v - mid) / half))
        .collect()
}

/// [`texture`], computed once per thread for the last set of arguments: a sequence draws
/// the same background in every frame.
fn cached_texture(width: usize, height: usize, mean: f64, t: Texture) -> Vec<f64> {
    type Key = (usize, usize, u64, u64, u64);
    thread_local! {
        static LAST: std::cell::RefCell<Option<(Key, Vec<f64>)>> =
            const { std::cell::RefCell::new(None) };
    }
    let key = (width, height, mean.to_bits(), t.seed, t.contrast.to_bits());
    LAST.with(|last| {
        let mut last = last.borrow_mut();
        match &*last {
            Some((k, pixels)) if *k == key => pixels.clone(),
            _ => {
                let pixels = texture(width, height, mean, t);
                *last = Some((key, pixels.clone()));
                pixels
            }
        }
    })
}

/// Gaussian blur of standard deviation `sigma` pixels, separable, kernel cut at 3σ, edges
/// clamped.
fn blur(buf: &mut [f64], width: usize, height: usize, sigma: f64) {
    let r = (3.0 * sigma).ceil() as isize;
    let kernel: Vec<f64> = (-r..=r)
        .map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp())
        .collect();
    let norm: f64 = kernel.iter().sum();
    let kernel: Vec<f64> = kernel.iter().map(|k| k / norm).collect();
    let mut tmp = vec![0.0; buf.len()];
    let clamp = |v: isize, n: usize| v.clamp(0, n as isize - 1) as usize;
    for j in 0..height {
        for i in 0..width {
            tmp[j * width + i] = kernel
                .iter()
                .enumerate()
                .map(|(k, w)| w * buf[j * width + clamp(i as isize + k as isize - r, width)])
                .sum();
        }
    }
    for j in 0..height {
        for i in 0..width {
            buf[j * width + i] = kernel
                .iter()
                .enumerate()
                .map(|(k, w)| w * tmp[clamp(j as isize + k as isize - r, height) * width + i])
                .sum();
        }
    }
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
    /// A dim, noisy weave ([`dim_weave_scene`], [`dim_weave`]): the board and its darkest
    /// paint 30 grey levels apart (0.42 and 0.30 of full scale, so the mid-tone edges have
    /// 15), on a vehicle body of 0.34, over a photographic-like background at 40 % contrast;
    /// blur σ = 0.9 px, then noise σ = 7; the target weaving ±28 px over 90 frames, its
    /// scale 1.05 ± 0.2 over 180.
    DimWeave,
}

impl SequenceKind {
    /// Every kind, in order.
    pub const ALL: [SequenceKind; 6] = [
        SequenceKind::Plain,
        SequenceKind::Clutter,
        SequenceKind::Swerve,
        SequenceKind::Shake,
        SequenceKind::Dim,
        SequenceKind::DimWeave,
    ];

    /// Lower-case name.
    pub fn as_str(self) -> &'static str {
        match self {
            SequenceKind::Plain => "plain",
            SequenceKind::Clutter => "clutter",
            SequenceKind::Swerve => "swerve",
            SequenceKind::Shake => "shake",
            SequenceKind::Dim => "dim",
            SequenceKind::DimWeave => "dim-weave",
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
        SequenceKind::DimWeave => dim_weave(start, frames, seed),
    };
    scenes_for(kind, truth, half_extent_px, seed)
}

/// Half the sideways travel of [`SequenceKind::DimWeave`], pixels.
pub const WEAVE_PX: f64 = 28.0;
/// The weave's period, frames (6 s at 15 Hz).
pub const WEAVE_PERIOD_FRAMES: f64 = 90.0;
/// The weave's swing of scale about 1.05 × the start's, and its period in frames.
pub const WEAVE_SCALE: (f64, f64) = (0.2, 180.0);

/// The truth of [`SequenceKind::DimWeave`]: c_x weaving ±[`WEAVE_PX`] about `start` with
/// period [`WEAVE_PERIOD_FRAMES`], c_y a gentle wander (up to 0.5 px a frame) about it,
/// and the scale `start.scale × 1.05 ± 0.2` (period 180 frames), both sines rising from
/// frame 0.
pub fn dim_weave(start: Location, frames: usize, seed: u64) -> Vec<Location> {
    let tau = std::f64::consts::TAU;
    wander(start, frames, 0.5, 0.0, seed)
        .into_iter()
        .enumerate()
        .map(|(k, w)| {
            let k = k as f64;
            let (swing, period) = WEAVE_SCALE;
            Location::new(
                start.c_x + WEAVE_PX * (tau * k / WEAVE_PERIOD_FRAMES).sin(),
                w.c_y,
                start.scale * (1.05 + swing * (tau * k / period).sin()),
            )
        })
        .collect()
}

/// The scene of [`SequenceKind::DimWeave`] (one for every frame; the target moves, the
/// background does not), its texture seeded by `seed`. Grey levels as fractions of full
/// scale (255): board 0.42, darkest paint 0.30 (30 levels below the board; the step-painted
/// target's mid tone is 15 from both), the vehicle's body 0.34, reaching 0.15 m beyond the
/// board's sides, 0.2 m above it and 0.55 m below; the background a [`Texture`] about 0.36
/// at 40 % contrast (92 ± 37 levels); blur σ = 0.9 px, then sensor noise σ = 7 levels.
pub fn dim_weave_scene(seed: u64) -> SynthScene {
    let level = |fraction: f64| fraction * 255.0;
    SynthScene {
        background: level(0.36),
        board: level(0.42),
        paint: level(0.30),
        noise_sigma: 7.0,
        texture: Some(Texture {
            seed: seed ^ 0x7e47_u64,
            contrast: 0.4,
        }),
        body: Some(Body {
            bounds_m: [-1.3, -1.4, 1.3, 1.05],
            value: level(0.34),
        }),
        blur_sigma: 0.9,
        ..SynthScene::default()
    }
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
    scenes_for(kind, truth, half_extent_px, 0)
}

/// The scenes of a sequence of `kind` for a given truth; `seed` seeds what a scene draws
/// besides its noise (the dim weave's background).
fn scenes_for(
    kind: SequenceKind,
    truth: Vec<Location>,
    half_extent_px: [f64; 2],
    seed: u64,
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
            SequenceKind::DimWeave => dim_weave_scene(seed),
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
