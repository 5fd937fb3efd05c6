//! The lens's and the sensor's effects on the rendered (already gain- and exposure-scaled)
//! image, applied on the CPU: vignetting, blur, shot noise and the additive read noise.
//!
//! The read noise is the last step, so recordings can take it away exactly and replays add
//! it back ([`shift_noise`]); vignetting and shot noise come before it, and a recording
//! keeps them as part of its image.

use crate::scene::{stream, Sensor};
use image::GrayImage;
use rand::RngCore;

/// Random words the noise stream reserves per frame: two, the key of that frame's pixel
/// hash. (ChaCha8 per pixel costs ~0.7 ms a frame, a quarter of the budget.)
const WORDS_PER_FRAME: u128 = 2;

/// Standard deviation of the sum of four independent uniform bytes (each 0..=255):
/// `sqrt(4 · (256² − 1) / 12)`. Such a sum is Gaussian to within 1 % of sigma out to 2.5 σ
/// (Irwin–Hall), and costs one 32-bit random word per pixel instead of a logarithm.
const SUM4_SIGMA: f32 = 147.800_54;

/// Applies, in place and in this order, the lens's cos⁴ vignetting and blur (optical, so
/// first), the shot noise (before the read-out) and the additive Gaussian read noise, for
/// a camera with the intrinsics `camera`. Frame `frame_index`'s noises are fixed slices of
/// the `"sensor-shot-noise"` and `"sensor-noise"` streams of `seed`. Each effect that is
/// off leaves the image untouched.
pub fn apply_sensor(
    image: &mut GrayImage,
    sensor: &Sensor,
    camera: &tracker::Camera,
    seed: u64,
    frame_index: u64,
) {
    let rows = 0..image.height() as usize;
    apply_sensor_to_rows(image, sensor, camera, seed, frame_index, rows);
}

/// [`apply_sensor`] on the rows `rows` alone (a renderer that drew only those rows need not
/// pay for the rest; the others are left as they are, but for the vignetting of those the
/// blur reads). Each pixel of those rows is what [`apply_sensor`] makes of it: every effect
/// but the blur is pixel by pixel, and the blur reads the rows within its reach.
pub fn apply_sensor_to_rows(
    image: &mut GrayImage,
    sensor: &Sensor,
    camera: &tracker::Camera,
    seed: u64,
    frame_index: u64,
    rows: std::ops::Range<usize>,
) {
    let (width, height) = (image.width() as usize, image.height() as usize);
    let rows = rows.start.min(rows.end)..rows.end.min(height);
    if sensor.vignetting > 0.0 {
        // Also the rows the blur reads around them.
        let reach = sensor.blur_sigma_px.map_or(0, blur_radius);
        let around = rows.start.saturating_sub(reach)..(rows.end + reach).min(height);
        vignette(image, sensor.vignetting, camera, around);
    }
    if let Some(sigma) = sensor.blur_sigma_px {
        blur(image, sigma, rows.clone());
    }
    let first = rows.start * width;
    let pixels = &mut image.as_mut()[first..rows.end * width];
    if let Some(full_well_e) = sensor.shot_noise_full_well_e {
        let table = match sensor.read_noise_e {
            None => shot_scale(full_well_e, 1.0, 0.0),
            Some(read_e) => shot_scale(full_well_e, sensor.gain, read_e),
        };
        add_shot_noise(pixels, first, &table, seed, frame_index);
    }
    if sensor.noise_sigma_grey <= 0.0 {
        return;
    }
    let (key, k) = frame_noise(sensor.noise_sigma_grey, seed, frame_index);
    add_noise(pixels, first, key, k);
}

/// Scales each pixel of the rows `rows` by the lens's cos⁴ law with strength `strength`
/// (0–1) for a camera with the intrinsics `camera`: by `1 − strength · (1 − cos⁴θ)`, θ the
/// angle between the pixel's ray and the optical axis (in f32, from each row's and each
/// column's share of tan²θ), rounding to the nearest grey level.
fn vignette(
    image: &mut GrayImage,
    strength: f64,
    camera: &tracker::Camera,
    rows: std::ops::Range<usize>,
) {
    let width = image.width() as usize;
    let tan2 = |offset_px: f64, axis: usize| {
        let t = offset_px * camera.pixel_size_mm[axis] / camera.focal_length_mm;
        (t * t) as f32
    };
    let [cx, cy] = camera.image_center_px;
    let columns: Vec<f32> = (0..width).map(|x| tan2(x as f64 - cx, 0)).collect();
    let s = strength as f32;
    let pixels = &mut image.as_mut()[rows.start * width..rows.end * width];
    for (y, row) in (rows.start..).zip(pixels.chunks_exact_mut(width)) {
        let row_tan2 = 1.0 + tan2(y as f64 - cy, 1);
        for (pixel, &column_tan2) in row.iter_mut().zip(&columns) {
            let cos2 = 1.0 / (row_tan2 + column_tan2);
            let factor = 1.0 - s * (1.0 - cos2 * cos2);
            // Non-negative and at most 255: adding a half and truncating rounds.
            *pixel = (f32::from(*pixel) * factor + 0.5) as u8;
        }
    }
}

/// Per grey level `v` of the output: the standard deviation of its sensor noise, grey
/// levels, over that of the hash's sum of four bytes ([`SUM4_SIGMA`]). The sensor noise
/// of a pixel of grey `v` at electronic gain `gain`, with `full_well_e` electrons at grey
/// 255 at gain 1 and read noise `read_e` electrons (rms) before the gain, has variance
/// `255 · gain · v / full_well_e + (255 · gain · read_e / full_well_e)²` grey levels²:
/// the Poisson spread of the `v · full_well_e / (255 · gain)` electrons collected, and the
/// read noise, both amplified by the gain (see [`Sensor::read_noise_e`]). At gain 1 and
/// without read noise this is the shot noise alone, `sqrt(255 · v / full_well_e)`.
pub fn sensor_noise_sigma_grey(v: f64, full_well_e: f64, gain: f64, read_e: f64) -> f64 {
    // Grey levels per electron.
    let per_e = 255.0 * gain / full_well_e;
    (per_e * v + (per_e * read_e).powi(2)).sqrt()
}

/// [`sensor_noise_sigma_grey`] of every grey level over [`SUM4_SIGMA`], in f32 (as the
/// shot noise has always been computed: the square root in f64, then rounded to f32).
fn shot_scale(full_well_e: f64, gain: f64, read_e: f64) -> Vec<f32> {
    (0..256)
        .map(|v| {
            let sigma = if gain == 1.0 && read_e == 0.0 {
                (255.0 * f64::from(v) / full_well_e).sqrt()
            } else {
                sensor_noise_sigma_grey(f64::from(v), full_well_e, gain, read_e)
            };
            (sigma as f32) / SUM4_SIGMA
        })
        .collect()
}

/// Adds the sensor's noise (shot noise, and read noise with [`Sensor::read_noise_e`]): a
/// pixel of grey `v` takes a Gaussian deviate of standard deviation `scale[v]` times
/// [`SUM4_SIGMA`] (see [`shot_scale`]). Pixel `i`'s deviate is the same hash as the read
/// noise's, keyed by frame `frame_index`'s words of the `"sensor-shot-noise"` stream.
/// `pixels` are the frame's pixels from index `first` on.
fn add_shot_noise(pixels: &mut [u8], first: usize, scale: &[f32], seed: u64, frame_index: u64) {
    let key = frame_key("sensor-shot-noise", seed, frame_index);
    for (i, pixel) in pixels.iter_mut().enumerate() {
        let z = sum4_centred(first + i, key) as f32;
        let v = f32::from(*pixel) + scale[usize::from(*pixel)] * z;
        // Clamped first, so adding a half and truncating rounds to nearest.
        *pixel = (v.clamp(0.0, 255.0) + 0.5) as u8;
    }
}

/// The key of frame `frame_index`'s pixel hash: a fixed slice of stream `name` of `seed`.
fn frame_key(name: &str, seed: u64, frame_index: u64) -> u64 {
    let mut rng = stream(seed, name);
    rng.set_word_pos(u128::from(frame_index) * WORDS_PER_FRAME);
    rng.next_u64()
}

/// Frame `frame_index`'s noise: the key of its pixel hash (a fixed slice of the
/// `"sensor-noise"` stream of `seed`) and the noise gain in 16.16 fixed point (integer
/// arithmetic rounds without a call to `roundf` per pixel: baseline x86-64 has no rounding
/// instruction).
fn frame_noise(noise_sigma_grey: f64, seed: u64, frame_index: u64) -> (u64, i32) {
    let k = (f64::from(noise_sigma_grey as f32 / SUM4_SIGMA) * FIXED_ONE).round() as i32;
    (frame_key("sensor-noise", seed, frame_index), k)
}

/// Adds (`sign` 1) or takes away (`sign` −1) the noise that frame `frame_index` of `seed`
/// adds (the same arithmetic as [`apply_sensor`]'s), writing `src` into `dst`, each pixel
/// clamped to 0–255. Recordings take it away and replays add it back: a noisy pixel `p`
/// with noise `d` was `clamp(v + d)` for some `v` in 0–255, so `p − d` is in 0–255 too, and
/// `clamp((p − d) + d) = p` exactly.
pub fn shift_noise(
    src: &[u8],
    dst: &mut Vec<u8>,
    noise_sigma_grey: f64,
    seed: u64,
    frame_index: u64,
    sign: i32,
) {
    dst.clear();
    if noise_sigma_grey <= 0.0 {
        dst.extend_from_slice(src);
        return;
    }
    let (key, k) = frame_noise(noise_sigma_grey, seed, frame_index);
    dst.resize(src.len(), 0);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, checked just above.
        unsafe { shift_noise_avx2(src, dst, key, k, sign) };
        return;
    }
    shift_noise_portable(src, dst, key, k, sign);
}

/// [`shift_noise_portable`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn shift_noise_avx2(src: &[u8], dst: &mut [u8], key: u64, k: i32, sign: i32) {
    shift_noise_portable(src, dst, key, k, sign);
}

/// The loop of [`shift_noise`]: the same integer arithmetic on every CPU.
#[inline(always)]
fn shift_noise_portable(src: &[u8], dst: &mut [u8], key: u64, k: i32, sign: i32) {
    for (i, (d, &p)) in dst.iter_mut().zip(src).enumerate() {
        *d = (i32::from(p) + sign * noise_delta(i, key, k)).clamp(0, 255) as u8;
    }
}

/// Pixel `i`'s noise for the frame key `key` and fixed-point gain `k`.
#[inline(always)]
fn noise_delta(i: usize, key: u64, k: i32) -> i32 {
    (k * sum4_centred(i, key) + FIXED_HALF) >> 16
}

/// Pixel `i`'s sum of four random bytes for the frame key `key`, less its mean (510):
/// zero-mean, standard deviation [`SUM4_SIGMA`].
#[inline(always)]
fn sum4_centred(i: usize, key: u64) -> i32 {
    let (key_lo, key_hi) = (key as u32, (key >> 32) as u32);
    // MurmurHash3's 32-bit finaliser of a Weyl sequence: a bijection with full avalanche,
    // so neighbouring pixels' words are unrelated.
    let mut x = ((i as u32).wrapping_mul(0x9e37_79b9) ^ key_lo).wrapping_add(key_hi);
    x ^= x >> 16;
    x = x.wrapping_mul(0x85eb_ca6b);
    x ^= x >> 13;
    x = x.wrapping_mul(0xc2b2_ae35);
    x ^= x >> 16;
    let sum = (x & 0xff) + ((x >> 8) & 0xff) + ((x >> 16) & 0xff) + (x >> 24);
    sum as i32 - 510
}

/// Adds noise to every pixel of `pixels`, the frame's pixels from index `first` on: pixel
/// `i`'s four random bytes are a hash of `i` keyed by the frame's random word, so pixels
/// are independent of each other and of the order they are computed in, and the loop
/// vectorises (with AVX2 where the CPU has it; the result is the
/// same integer arithmetic either way, so frames do not depend on the CPU).
fn add_noise(pixels: &mut [u8], first: usize, key: u64, k: i32) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, checked just above.
        unsafe { add_noise_avx2(pixels, first, key, k) };
        return;
    }
    add_noise_portable(pixels, first, key, k);
}

/// [`add_noise_portable`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn add_noise_avx2(pixels: &mut [u8], first: usize, key: u64, k: i32) {
    add_noise_portable(pixels, first, key, k);
}

/// The noise loop itself (see [`add_noise`]).
#[inline(always)]
fn add_noise_portable(pixels: &mut [u8], first: usize, key: u64, k: i32) {
    for (i, pixel) in pixels.iter_mut().enumerate() {
        *pixel = (i32::from(*pixel) + noise_delta(first + i, key, k)).clamp(0, 255) as u8;
    }
}

/// 1.0 in the 16.16 fixed point the noise is scaled in.
const FIXED_ONE: f64 = 65_536.0;
/// 0.5 in that fixed point: added before the shift, it rounds to nearest.
const FIXED_HALF: i32 = 32_768;

/// How far the sensor's blur reaches, pixels: a pixel's value depends on the rendered
/// pixels up to this far away in each direction (0 without blur).
pub fn blur_reach_px(sensor: &Sensor) -> usize {
    sensor.blur_sigma_px.map_or(0, blur_radius)
}

/// The blur kernel's radius for `sigma`, pixels: 2.5 σ (the weights beyond are below 5 %
/// of the centre's).
fn blur_radius(sigma: f64) -> usize {
    (2.5 * sigma).ceil().max(1.0) as usize
}

/// Separable Gaussian blur with standard deviation `sigma` pixels, edges clamped, of the
/// rows `rows` (reading the rows within the blur's reach of them).
fn blur(image: &mut GrayImage, sigma: f64, rows: std::ops::Range<usize>) {
    let radius = blur_radius(sigma) as i64;
    let weights: Vec<f32> = (-radius..=radius)
        .map(|k| (-(k * k) as f64 / (2.0 * sigma * sigma)).exp() as f32)
        .collect();
    let total: f32 = weights.iter().sum();
    let (w, h) = (image.width() as i64, image.height() as i64);
    let (y0, y1) = (rows.start as i64, rows.end as i64);
    let src: Vec<f32> = image.iter().map(|&p| f32::from(p)).collect();
    let mut tmp = vec![0f32; src.len()];
    // The horizontal pass on the rows the vertical one reads.
    for y in (y0 - radius).max(0)..(y1 + radius).min(h) {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, wt) in weights.iter().enumerate() {
                let xx = (x + i as i64 - radius).clamp(0, w - 1);
                acc += wt * src[(y * w + xx) as usize];
            }
            tmp[(y * w + x) as usize] = acc / total;
        }
    }
    for y in y0..y1 {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, wt) in weights.iter().enumerate() {
                let yy = (y + i as i64 - radius).clamp(0, h - 1);
                acc += wt * tmp[(yy * w + x) as usize];
            }
            image.as_mut()[(y * w + x) as usize] = (acc / total).round().clamp(0.0, 255.0) as u8;
        }
    }
}

#[cfg(test)]
mod shift_tests {
    use super::*;

    #[test]
    fn the_sensor_on_some_rows_gives_those_rows_of_the_whole_frame() {
        let (w, h) = (64u32, 48u32);
        let image = GrayImage::from_fn(w, h, |x, y| image::Luma([((x * 7 + y * 13) % 256) as u8]));
        let sensor = Sensor {
            noise_sigma_grey: 6.0,
            blur_sigma_px: Some(1.2),
            vignetting: 0.6,
            shot_noise_full_well_e: Some(2000.0),
            ..Sensor::default()
        };
        let camera = tracker::Camera::default();
        let mut whole = image.clone();
        apply_sensor(&mut whole, &sensor, &camera, 7, 3);
        for rows in [0..h as usize, 10..20, 0..5, 40..48, 17..17] {
            let mut part = image.clone();
            apply_sensor_to_rows(&mut part, &sensor, &camera, 7, 3, rows.clone());
            let row =
                |img: &GrayImage, y: usize| img.as_raw()[y * w as usize..][..w as usize].to_vec();
            for y in rows.clone() {
                assert_eq!(row(&part, y), row(&whole, y), "rows {rows:?}, row {y}");
            }
        }
    }

    #[test]
    fn noise_taken_away_and_added_back_gives_the_noisy_frame_exactly() {
        // Every grey level, saturated ones included, under strong noise.
        let clean: Vec<u8> = (0..256 * 64).map(|i| (i % 256) as u8).collect();
        let sensor = Sensor {
            noise_sigma_grey: 20.0,
            ..Sensor::default()
        };
        for frame in [0, 7, 1234] {
            let mut noisy = GrayImage::from_raw(256, 64, clean.clone()).unwrap();
            apply_sensor(&mut noisy, &sensor, &tracker::Camera::default(), 42, frame);
            let (mut quiet, mut back) = (Vec::new(), Vec::new());
            shift_noise(noisy.as_raw(), &mut quiet, 20.0, 42, frame, -1);
            shift_noise(&quiet, &mut back, 20.0, 42, frame, 1);
            assert_eq!(back, noisy.as_raw().to_vec(), "frame {frame}");
            // Away from saturation, taking the noise away gives the clean frame.
            let restored = quiet
                .iter()
                .zip(&clean)
                .filter(|(_, &c)| (80..=175).contains(&c))
                .all(|(q, c)| q == c);
            assert!(restored, "frame {frame}");
            // Another frame's noise does not undo this one's.
            let mut wrong = Vec::new();
            shift_noise(noisy.as_raw(), &mut wrong, 20.0, 42, frame + 1, -1);
            assert_ne!(wrong, quiet);
        }
    }
}

#[cfg(test)]
mod effect_tests {
    use super::*;

    /// A flat 256×242 frame of grey `level` through `sensor` (the default camera), frame
    /// `frame` of `seed`.
    fn sensed(level: u8, sensor: &Sensor, seed: u64, frame: u64) -> GrayImage {
        let mut image = GrayImage::from_pixel(256, 242, image::Luma([level]));
        apply_sensor(&mut image, sensor, &tracker::Camera::default(), seed, frame);
        image
    }

    #[test]
    fn vignetting_darkens_a_flat_scene_by_the_cos4_law() {
        let sensor = Sensor {
            noise_sigma_grey: 0.0,
            vignetting: 1.0,
            ..Sensor::default()
        };
        let image = sensed(200, &sensor, 1, 0);
        // The corner (0, 0) sees at θ with tan²θ = (127.5² + 120.5²) / 320².
        let tan2 = (127.5f64.powi(2) + 120.5f64.powi(2)) / 320.0f64.powi(2);
        let cos4 = (1.0 / (1.0 + tan2)).powi(2);
        for (x, y) in [(0, 0), (255, 0), (0, 241), (255, 241)] {
            let v = f64::from(image.get_pixel(x, y)[0]);
            assert!((v - 200.0 * cos4).abs() <= 0.5, "({x}, {y}): {v}");
        }
        // The centre is untouched, and a half-strength lens darkens the corner half as much.
        assert_eq!(image.get_pixel(127, 120)[0], 200);
        let sensor = Sensor {
            vignetting: 0.5,
            ..sensor
        };
        let half = sensed(200, &sensor, 1, 0);
        let v = f64::from(half.get_pixel(0, 0)[0]);
        assert!((v - 200.0 * (1.0 - 0.5 * (1.0 - cos4))).abs() <= 0.5, "{v}");
    }

    /// The variance of a flat frame of `level` under `sensor` (seed `seed`, frame `frame`),
    /// its mean checked to be `level` within `mean_tolerance`.
    fn flat_variance(
        level: u8,
        sensor: &Sensor,
        seed: u64,
        frame: u64,
        mean_tolerance: f64,
    ) -> f64 {
        let image = sensed(level, sensor, seed, frame);
        let n = image.as_raw().len() as f64;
        let mean = image.iter().map(|&p| f64::from(p)).sum::<f64>() / n;
        assert!((mean - f64::from(level)).abs() < mean_tolerance, "{mean}");
        image
            .iter()
            .map(|&p| (f64::from(p) - mean).powi(2))
            .sum::<f64>()
            / n
    }

    /// The variance of a flat frame of `level` under shot noise only.
    fn shot_variance(level: u8, full_well_e: f64, frame: u64) -> f64 {
        let sensor = Sensor {
            noise_sigma_grey: 0.0,
            shot_noise_full_well_e: Some(full_well_e),
            ..Sensor::default()
        };
        flat_variance(level, &sensor, 7, frame, 0.05)
    }

    #[test]
    fn shot_noise_variance_grows_with_the_signal() {
        let full_well_e = 2000.0;
        for level in [20u8, 80, 200] {
            // Poisson: variance 255 · v / full well, grey levels², plus 1/12 of rounding.
            let expected = 255.0 * f64::from(level) / full_well_e + 1.0 / 12.0;
            let got = shot_variance(level, full_well_e, 3);
            assert!(
                (got / expected - 1.0).abs() < 0.05,
                "{level}: {got} vs {expected}"
            );
        }
        assert!(shot_variance(0, full_well_e, 3) == 0.0);
    }

    /// The variance of a flat frame of `level` under the gain-referred sensor noise alone.
    fn low_light_variance(level: u8, gain: f64, read_e: f64) -> f64 {
        let sensor = Sensor {
            noise_sigma_grey: 0.0,
            gain,
            shot_noise_full_well_e: Some(20_000.0),
            read_noise_e: Some(read_e),
            ..Sensor::default()
        };
        flat_variance(level, &sensor, 11, 5, 0.1)
    }

    #[test]
    fn low_light_noise_follows_shot_and_read_noise_at_the_gain() {
        // A dark patch brought up to grey 40 by gains 1, 8 and 32: the same grey, from 8
        // and 32 times fewer electrons, so noisier; within 5 % of the formula's variance
        // (plus 1/12 for the rounding) over 62 000 pixels.
        let mut last = 0.0;
        for gain in [1.0, 8.0, 32.0] {
            let sigma = sensor_noise_sigma_grey(40.0, 20_000.0, gain, 10.0);
            let expected = sigma * sigma + 1.0 / 12.0;
            let got = low_light_variance(40, gain, 10.0);
            assert!(
                (got / expected - 1.0).abs() < 0.05,
                "gain {gain}: {got} vs {expected}"
            );
            assert!(got > last);
            last = got;
        }
        // Without the read noise (4.08 grey levels at gain 32: 255 · 32 · 10 / 20 000), the
        // shot noise alone.
        let sigma = sensor_noise_sigma_grey(40.0, 20_000.0, 32.0, 0.0);
        let shot_only = low_light_variance(40, 32.0, 0.0);
        let expected = sigma * sigma + 1.0 / 12.0;
        assert!(
            (shot_only / expected - 1.0).abs() < 0.05,
            "{shot_only} vs {expected}"
        );
        assert!(
            last - shot_only > 0.9 * 4.08 * 4.08,
            "{last} vs {shot_only}"
        );
        // At gain 1 without read noise the model is the shot noise as it always was.
        let gain_referred = Sensor {
            shot_noise_full_well_e: Some(2000.0),
            read_noise_e: Some(0.0),
            ..Sensor::default()
        };
        let plain = Sensor {
            read_noise_e: None,
            ..gain_referred.clone()
        };
        assert_eq!(sensed(90, &gain_referred, 2, 3), sensed(90, &plain, 2, 3));
    }

    #[test]
    fn the_effects_are_seeded_and_off_by_default() {
        let sensor = Sensor {
            shot_noise_full_well_e: Some(1000.0),
            vignetting: 0.7,
            ..Sensor::default()
        };
        let noisy = |seed, frame| sensed(120, &sensor, seed, frame);
        assert_eq!(noisy(5, 9), noisy(5, 9));
        assert_ne!(noisy(5, 9), noisy(5, 10));
        assert_ne!(noisy(5, 9), noisy(6, 9));
        // Off, the frame is the read noise's alone.
        let plain = sensed(120, &Sensor::default(), 5, 9);
        let mut read_only = Vec::new();
        shift_noise(&[120; 256 * 242], &mut read_only, 2.0, 5, 9, 1);
        assert_eq!(plain.as_raw(), &read_only);
    }

    #[test]
    fn the_read_noise_of_a_frame_with_shot_noise_is_taken_away_exactly() {
        let sensor = Sensor {
            shot_noise_full_well_e: Some(500.0),
            noise_sigma_grey: 6.0,
            ..Sensor::default()
        };
        let quiet_sensor = Sensor {
            noise_sigma_grey: 0.0,
            ..sensor.clone()
        };
        let shot_only = sensed(90, &quiet_sensor, 3, 4);
        let both = sensed(90, &sensor, 3, 4);
        let mut quiet = Vec::new();
        shift_noise(both.as_raw(), &mut quiet, 6.0, 3, 4, -1);
        assert_eq!(&quiet, shot_only.as_raw());
    }
}
