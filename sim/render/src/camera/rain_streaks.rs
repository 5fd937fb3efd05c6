//! Rain's streaks: the drops near the camera, each drawn as the line it moves along during
//! the exposure, on the frame's radiance (after the gain, before the sensor's noise).
//!
//! A frame's drops are drawn from frame `frame_index`'s slice of the `"rain-streaks"`
//! stream of the scene's seed, so the streaks change from frame to frame, the same frame
//! is the same whichever renderer draws it, and rain moves no other random draw.

use crate::scene::{stream, Rain};
use image::GrayImage;
use nalgebra::{Point3, UnitQuaternion, Vector3};
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random words the streaks' stream reserves per frame: two, the key of that frame's own
/// generator.
const WORDS_PER_FRAME: u128 = 2;

/// A drop's end nearer than this to the camera's plane, metres, leaves its streak undrawn
/// (a drop passing the lens within the exposure).
const MIN_END_DEPTH_M: f64 = 0.05;

/// What a frame's streaks are drawn with besides the rain.
pub struct StreakView<'a> {
    /// The camera's intrinsics.
    pub camera: &'a tracker::Camera,
    /// The camera frame from the world (rotation only: velocities).
    pub camera_from_world: UnitQuaternion<f64>,
    /// The camera's velocity in the world, m/s (the chase's).
    pub camera_velocity: Vector3<f64>,
    /// The exposure, seconds.
    pub exposure_s: f64,
    /// The drops' grey (their radiance times the sensor's brightness), 0–255.
    pub drop_grey: f64,
    /// The first row the chase's hood covers: the streaks are drawn above it (the drops
    /// fall beyond the hood).
    pub hood_row: usize,
}

/// Draws the streaks of frame `frame_index` of `rain` on `image`, with scene seed `seed`.
/// Their number is [`Rain::visible_drops`] (its fraction drawn as one more with that
/// chance); each drop's diameter is drawn from Marshall–Palmer's sizes weighted by the
/// volume it is seen in (`D³ e^(−ΛD)`, a gamma of shape 4), its depth uniform in that
/// volume (`z_max ∛u`), its place uniform in the image. It moves at its fall speed
/// ([`Rain::fall_speed_mps`]) less the camera's velocity; its streak joins its image at the
/// start and end of the exposure. Each pixel along the line takes `α` of the drop's grey:
/// the share of the pixel its image covers (its width, up to 1) times the share of the
/// exposure it spends there (its width over the streak's length, up to 1). Returns how many
/// streaks were drawn.
pub fn draw_streaks(
    image: &mut GrayImage,
    rain: &Rain,
    view: &StreakView,
    seed: u64,
    frame_index: u64,
) -> usize {
    let (width, height) = (image.width() as usize, image.height() as usize);
    let [fx, fy] = view.camera.focal_px();
    let expected = rain.visible_drops([fx, fy], width as f64, height as f64);
    let mut rng = {
        let mut s = stream(seed, "rain-streaks");
        s.set_word_pos(u128::from(frame_index) * WORDS_PER_FRAME);
        ChaCha8Rng::seed_from_u64(s.next_u64())
    };
    let count = expected.floor() as usize + usize::from(rng.random::<f64>() < expected.fract());
    let lambda = rain.slope_per_mm();
    let fall = view.camera_from_world * Vector3::new(0.0, -1.0, 0.0);
    let camera_velocity = view.camera_from_world * view.camera_velocity;
    let [cx, cy] = view.camera.image_center_px;
    let mut drawn = 0;
    for _ in 0..count {
        // Seven uniforms a drop, drawn whether or not it is kept, so that each drop's
        // numbers are the same whatever the others'.
        let u: [f64; 7] = std::array::from_fn(|_| 1.0 - rng.random::<f64>());
        let diameter_mm = -(u[0].ln() + u[1].ln() + u[2].ln() + u[3].ln()) / lambda;
        if diameter_mm > Rain::MAX_DROP_MM {
            continue;
        }
        let z_max = fx * diameter_mm * 1e-3 / Rain::MIN_DROP_PX;
        let z = z_max * u[4].cbrt();
        if z < Rain::NEAREST_DROP_M {
            continue;
        }
        let (px, py) = (u[5] * width as f64 - 0.5, u[6] * height as f64 - 0.5);
        let centre = Point3::new((px - cx) * z / fx, (py - cy) * z / fy, z);
        let velocity = fall * Rain::fall_speed_mps(diameter_mm) - camera_velocity;
        let half = velocity * (0.5 * view.exposure_s);
        let (a, b) = (centre - half, centre + half);
        if a.z < MIN_END_DEPTH_M || b.z < MIN_END_DEPTH_M {
            continue;
        }
        let (Some(pa), Some(pb)) = (
            view.camera.project([a.x, a.y, a.z]),
            view.camera.project([b.x, b.y, b.z]),
        ) else {
            continue;
        };
        let width_px = fx * diameter_mm * 1e-3 / z;
        let length_px = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let alpha = width_px.min(1.0) * (width_px / length_px.max(width_px)).min(1.0);
        line(image, pa, pb, alpha, view.drop_grey, view.hood_row);
        drawn += 1;
    }
    drawn
}

/// Blends `grey` with weight `alpha` into the pixels along the line from `a` to `b`
/// (pixel centres at integer coordinates; one pixel per step along its major axis), in
/// the rows above `hood_row`, rounding to the nearest grey level.
fn line(image: &mut GrayImage, a: [f64; 2], b: [f64; 2], alpha: f64, grey: f64, hood_row: usize) {
    let (width, height) = (image.width() as i64, image.height() as i64);
    let rows = height.min(hood_row as i64);
    let steps = (b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil().max(1.0);
    let n = steps as i64;
    let pixels = image.as_mut();
    for i in 0..=n {
        let t = i as f64 / steps;
        let x = (a[0] + t * (b[0] - a[0])).round() as i64;
        let y = (a[1] + t * (b[1] - a[1])).round() as i64;
        if x < 0 || x >= width || y < 0 || y >= rows {
            continue;
        }
        let p = &mut pixels[(y * width + x) as usize];
        let v = f64::from(*p) + alpha * (grey - f64::from(*p));
        *p = (v.clamp(0.0, 255.0) + 0.5) as u8;
    }
}
