//! The sensor's noise and blur, applied to the rendered (already gain- and
//! exposure-scaled) image on the CPU.

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

/// Applies blur (optical, so first) and then additive Gaussian noise to `image`, in place.
/// Frame `frame_index`'s noise is a fixed slice of the `"sensor-noise"` stream of `seed`.
pub fn apply_sensor(image: &mut GrayImage, sensor: &Sensor, seed: u64, frame_index: u64) {
    if let Some(sigma) = sensor.blur_sigma_px {
        blur(image, sigma);
    }
    if sensor.noise_sigma_grey <= 0.0 {
        return;
    }
    let (key, k) = frame_noise(sensor.noise_sigma_grey, seed, frame_index);
    add_noise(image.as_mut(), key, k);
}

/// Frame `frame_index`'s noise: the key of its pixel hash (a fixed slice of the
/// `"sensor-noise"` stream of `seed`) and the noise gain in 16.16 fixed point (integer
/// arithmetic rounds without a call to `roundf` per pixel: baseline x86-64 has no rounding
/// instruction).
fn frame_noise(noise_sigma_grey: f64, seed: u64, frame_index: u64) -> (u64, i32) {
    let mut rng = stream(seed, "sensor-noise");
    rng.set_word_pos(u128::from(frame_index) * WORDS_PER_FRAME);
    let k = (f64::from(noise_sigma_grey as f32 / SUM4_SIGMA) * FIXED_ONE).round() as i32;
    (rng.next_u64(), k)
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
    (k * (sum as i32 - 510) + FIXED_HALF) >> 16
}

/// Adds noise to every pixel: pixel `i`'s four random bytes are a hash of `i` keyed by the
/// frame's random word, so pixels are independent of each other and of the order they are
/// computed in, and the loop vectorises (with AVX2 where the CPU has it; the result is the
/// same integer arithmetic either way, so frames do not depend on the CPU).
fn add_noise(pixels: &mut [u8], key: u64, k: i32) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, checked just above.
        unsafe { add_noise_avx2(pixels, key, k) };
        return;
    }
    add_noise_portable(pixels, key, k);
}

/// [`add_noise_portable`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn add_noise_avx2(pixels: &mut [u8], key: u64, k: i32) {
    add_noise_portable(pixels, key, k);
}

/// The noise loop itself (see [`add_noise`]).
#[inline(always)]
fn add_noise_portable(pixels: &mut [u8], key: u64, k: i32) {
    for (i, pixel) in pixels.iter_mut().enumerate() {
        *pixel = (i32::from(*pixel) + noise_delta(i, key, k)).clamp(0, 255) as u8;
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

/// Separable Gaussian blur with standard deviation `sigma` pixels, edges clamped.
fn blur(image: &mut GrayImage, sigma: f64) {
    let radius = blur_radius(sigma) as i64;
    let weights: Vec<f32> = (-radius..=radius)
        .map(|k| (-(k * k) as f64 / (2.0 * sigma * sigma)).exp() as f32)
        .collect();
    let total: f32 = weights.iter().sum();
    let (w, h) = (image.width() as i64, image.height() as i64);
    let src: Vec<f32> = image.iter().map(|&p| f32::from(p)).collect();
    let mut tmp = vec![0f32; src.len()];
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, wt) in weights.iter().enumerate() {
                let xx = (x + i as i64 - radius).clamp(0, w - 1);
                acc += wt * src[(y * w + xx) as usize];
            }
            tmp[(y * w + x) as usize] = acc / total;
        }
    }
    for y in 0..h {
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
    fn noise_taken_away_and_added_back_gives_the_noisy_frame_exactly() {
        // Every grey level, saturated ones included, under strong noise.
        let clean: Vec<u8> = (0..256 * 64).map(|i| (i % 256) as u8).collect();
        let sensor = Sensor {
            noise_sigma_grey: 20.0,
            ..Sensor::default()
        };
        for frame in [0, 7, 1234] {
            let mut noisy = GrayImage::from_raw(256, 64, clean.clone()).unwrap();
            apply_sensor(&mut noisy, &sensor, 42, frame);
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
